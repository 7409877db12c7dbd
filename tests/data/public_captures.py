"""Public DCA1000 captures whose source states the scene, and where a test finds them.

None of them ships with the project: their licences do not allow it (see ``README.md`` in this
folder). Each entry names where the capture is published, its size and SHA-256, the profile we
wrote for it and what its source says was in front of the radar; the tests in
``tests/harness/test_cmd_ti_real.py`` check the harness reports exactly that and skip when the
file is absent.

A capture is looked for in ``$RADAR_HARNESS_CAPTURES/<file name>`` and then in
``tests/data/external/<file name>`` (ignored by git). To put it there from a copy of its
source (a TI toolbox installed from TI's site, or a public mirror of it)::

    python -m tests.data.public_captures install ti_iwr6843_anechoic_reflector PATH

where PATH is the capture itself or the folder it was published in (the toolbox root): the
file is found, its size and SHA-256 checked, and copied.
"""
from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import sys
from dataclasses import dataclass
from pathlib import Path

__all__ = ["PublicCapture", "PUBLIC_CAPTURES", "DATA_DIR", "find_capture", "install"]

#: This folder (profiles we wrote for the captures live here).
DATA_DIR = Path(__file__).resolve().parent
#: Where installed captures go (git ignores it).
EXTERNAL_DIR = DATA_DIR / "external"
#: Environment variable naming another folder that holds captures.
ENV_VAR = "RADAR_HARNESS_CAPTURES"


@dataclass(frozen=True, slots=True)
class PublicCapture:
    """One public capture: where it is published, how to recognise it, what its source says.

    Attributes
    ----------
    name : str
        Key, and the file name it is installed under (``<name>.bin``).
    source_path : str
        Path of the capture inside its publication (found under an install folder).
    size_bytes, sha256 : int, str
        Of the published file.
    profile : str
        Our TI profile for it, in this folder.
    stated : str
        What the source says was in front of the radar (quoted in the test's assertions).
    """

    name: str
    publication: str
    source_path: str
    size_bytes: int
    sha256: str
    licence: str
    profile: str
    stated: str

    @property
    def file_name(self) -> str:
        return f"{self.name}.bin"

    @property
    def profile_path(self) -> Path:
        return DATA_DIR / self.profile


PUBLIC_CAPTURES: dict[str, PublicCapture] = {c.name: c for c in (
    PublicCapture(
        name="ti_iwr6843_anechoic_reflector",
        publication="TI mmWave Industrial Toolbox 4.7.0, tools/memory_compression (also in the "
                    "public GitHub mirror topnav-dev/mmwave_industrial_toolbox_4_7_0, commit "
                    "8b3c982e0b6928a7a3899098f0cf61cd471c3154)",
        source_path="tools/memory_compression/data/adc_data_Raw_0.bin",
        size_bytes=786_432,
        sha256="cb0b7682258ef06172c19ff918dd9c525af88b8029102f7747880dcb1c3c56c3",
        licence="TI Evaluation, Development and Demonstration Software License (toolbox "
                "license/SRAS-3841-325565-v1-Radar_Demo_Clickwrap.pdf): no distribution",
        profile="ti_iwr6843_anechoic_reflector.cfg",
        stated="IWR6843 ES2.0 + MMWAVEICBOOST + DCA1000; 'captured in an Anechoic Chamber "
               "with a strong corner reflector, which results a distinct peak in the "
               "range-Doppler heat-map plot at range Bin of 38 and zero Doppler bin' "
               "(radar_memoryCompressionModel_iwr6843_users_guide.pdf sec. 2); 256 ADC samples, "
               "64 chirps, 12 virtual antennas in TDM-MIMO (setSystemParam.m, test_main.m: "
               "'Corner reflector around bin #38'), one frame",
    ),
)}


def _search_dirs() -> list[Path]:
    dirs = []
    if os.environ.get(ENV_VAR):
        dirs.append(Path(os.environ[ENV_VAR]))
    dirs.append(EXTERNAL_DIR)
    return dirs


def find_capture(name: str) -> Path | None:
    """Path of an installed capture whose size matches, or None (the tests then skip)."""
    cap = PUBLIC_CAPTURES[name]
    for d in _search_dirs():
        p = d / cap.file_name
        if p.is_file() and p.stat().st_size == cap.size_bytes:
            return p
    return None


def _sha256(path: Path) -> str:
    with open(path, "rb") as fh:
        return hashlib.file_digest(fh, "sha256").hexdigest()


def install(name: str, source: str | os.PathLike, dest_dir: Path = EXTERNAL_DIR) -> Path:
    """Copy capture `name` from `source` (the file, or the folder it was published in) into
    `dest_dir` after checking its size and SHA-256.

    Raises
    ------
    ValueError
        Unknown name, file not found under `source`, or size / SHA-256 not the published ones.
    """
    if name not in PUBLIC_CAPTURES:
        raise ValueError(f"unknown capture {name!r}; known: {', '.join(PUBLIC_CAPTURES)}")
    cap = PUBLIC_CAPTURES[name]
    src = Path(source)
    if src.is_dir():
        src = src / cap.source_path
    if not src.is_file():
        raise ValueError(f"{src} not found (expected {cap.source_path} under the folder)")
    if src.stat().st_size != cap.size_bytes or _sha256(src) != cap.sha256:
        raise ValueError(f"{src}: {src.stat().st_size} bytes, not the published capture "
                         f"({cap.size_bytes} bytes, SHA-256 {cap.sha256})")
    dest_dir.mkdir(parents=True, exist_ok=True)
    out = dest_dir / cap.file_name
    shutil.copyfile(src, out)
    return out


def _main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tests.data.public_captures",
                                     description="list or install the public captures the "
                                                 "real-capture tests use")
    sub = parser.add_subparsers(dest="cmd", required=True)
    sub.add_parser("list", help="known captures, where they are published, whether installed")
    ins = sub.add_parser("install", help="copy a capture from its publication, checked")
    ins.add_argument("name", choices=sorted(PUBLIC_CAPTURES))
    ins.add_argument("source", help="the capture file or the folder it was published in")
    args = parser.parse_args(argv)
    if args.cmd == "list":
        for cap in PUBLIC_CAPTURES.values():
            where = find_capture(cap.name)
            print(f"{cap.name}: {cap.publication}: {cap.source_path} "
                  f"({'installed at ' + str(where) if where else 'not installed'})")
        return 0
    try:
        print(install(args.name, args.source))
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(_main())
