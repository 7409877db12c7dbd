"""`ExternalChain`: a receive chain that runs as a separate process (software in the loop).

A sweep file declares one per ``[[external_chains]]`` table::

    [[external_chains]]
    name = "my_dsp"          # its value in the scheme column
    scheme = "tdma"          # the transmit scheme whose ADC frames it receives
    command = ["./my_dsp", "--cfg", "{cfg}", "--adc", "{adc}", "--out", "{points}"]
    timeout_s = 60           # per call; its whole process group is killed past it
    frames_per_call = 1      # or "cell": all frames of the cell in one call
    points = "points.csv"    # optional: the file name {points} gets (.csv or .parquet)

Placeholders: ``{cfg}`` the cell's TI profile, ``{adc}`` the DCA1000 capture, ``{points}`` the
point file to write, ``{here}`` the sweep file's folder, ``{python}`` the harness's Python
interpreter. The command runs in a scratch folder; a relative first word with a ``/``
(``./my_dsp``) is resolved against the sweep file's folder. The SHA-256 of every file the
command names (its program, its script) enters the chain's identity, so editing the script
recomputes its cells.
"""
from __future__ import annotations

import hashlib
import string
import sys
from dataclasses import dataclass
from pathlib import Path

from core.checks import check_keys
from core.errors import BadInput

__all__ = ["ExternalChain", "external_chains_from_toml", "PLACEHOLDERS", "MAX_TIMEOUT_S",
           "POINT_SUFFIXES"]

#: Placeholders a command may use.
PLACEHOLDERS = ("cfg", "adc", "points", "here", "python")
#: Longest timeout of one call, s.
MAX_TIMEOUT_S = 3600.0
#: Point-file formats by suffix.
POINT_SUFFIXES = (".csv", ".parquet")
#: Most frames in one call (a number; "cell" takes the whole cell).
MAX_FRAMES_PER_CALL = 100_000
_KEYS = {"name", "scheme", "command", "timeout_s", "frames_per_call", "points"}


@dataclass(frozen=True)
class ExternalChain:
    """One external receive chain (see the module docstring).

    Raises
    ------
    ValueError
        A name that is not an identifier, a command that is not a non-empty list of strings
        or lacks ``{points}``, an unknown placeholder, a timeout outside (0, 3600] s,
        frames_per_call not a positive integer or "cell", a points file that is not .csv or
        .parquet.
    """

    name: str
    scheme: str
    command: tuple[str, ...]
    timeout_s: float = 60.0
    frames_per_call: int | str = 1
    points: str = "points.csv"
    here: str = "."
    files_sha256: str = ""

    def __post_init__(self) -> None:
        w = f"external_chains {self.name!r}"
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise BadInput(f"external_chains name={self.name!r} must be an identifier (it is "
                           "a value of the scheme column)")
        if not isinstance(self.scheme, str) or not self.scheme:
            raise BadInput(f"{w}: scheme={self.scheme!r} must be a MIMO scheme name")
        cmd = self.command
        if isinstance(cmd, str) or not isinstance(cmd, (list, tuple)) or not cmd or \
                not all(isinstance(a, str) and a for a in cmd):
            raise BadInput(f"{w}: command={cmd!r} must be a non-empty list of non-empty "
                           "strings (the program and its arguments)")
        object.__setattr__(self, "command", tuple(cmd))
        used = set()
        for arg in self.command:
            try:
                used |= {f for _, f, _, _ in string.Formatter().parse(arg) if f is not None}
            except ValueError as exc:
                raise BadInput(f"{w}: command argument {arg!r}: {exc}") from None
        bad = sorted(used - set(PLACEHOLDERS))
        if bad:
            raise BadInput(f"{w}: command uses unknown placeholder(s) {bad}; known: "
                           f"{list(PLACEHOLDERS)}")
        if "points" not in used:
            raise BadInput(f"{w}: command must name the point file it writes: {{points}}")
        t = self.timeout_s
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not 0 < t <= MAX_TIMEOUT_S:
            raise BadInput(f"{w}: timeout_s={t!r} must be a number in (0, {MAX_TIMEOUT_S:g}] s")
        n = self.frames_per_call
        if n != "cell" and (isinstance(n, bool) or not isinstance(n, int)
                            or not 1 <= n <= MAX_FRAMES_PER_CALL):
            raise BadInput(f"{w}: frames_per_call={n!r} must be an integer in "
                           f"1..{MAX_FRAMES_PER_CALL} or \"cell\"")
        p = self.points
        if not isinstance(p, str) or Path(p).name != p or Path(p).suffix.lower() \
                not in POINT_SUFFIXES:
            raise BadInput(f"{w}: points={p!r} must be a file name ending in "
                           f"{' or '.join(POINT_SUFFIXES)}")

    def argv(self, cfg: str, adc: str, points: str) -> list[str]:
        """The command with its placeholders filled in; a relative program path with a ``/``
        resolved against the sweep file's folder."""
        values = {"cfg": cfg, "adc": adc, "points": points, "here": self.here,
                  "python": sys.executable}
        args = [a.format(**values) for a in self.command]
        prog = Path(args[0])
        if not prog.is_absolute() and "/" in args[0]:
            args[0] = str(Path(self.here) / prog)
        return args


def _files_sha256(chain: ExternalChain) -> str:
    """SHA-256 (16 hex digits) of every existing file the command names (its program, its
    script; not ``{python}``, the interpreter, whose version the code version holds)."""
    h = hashlib.sha256()
    for arg in chain.argv("{cfg}", "{adc}", "{points}"):
        p = Path(arg)
        if p.is_absolute() and p.is_file() and arg != sys.executable:
            h.update(p.name.encode() + b"\0" + p.read_bytes())
    return h.hexdigest()[:16]


def external_chains_from_toml(where: str, value, here: Path) -> tuple[ExternalChain, ...]:
    """`ExternalChain` of every ``[[external_chains]]`` table of a sweep file.

    Raises
    ------
    ValueError
        Naming the file, the table index and the bad key; duplicate names.
    """
    if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
        raise BadInput(f"{where}: external_chains must be an array of [[external_chains]] "
                       "tables")
    out = []
    for i, table in enumerate(value):
        try:
            check_keys(table, _KEYS, f"external_chains[{i}].")
            for key in ("name", "scheme", "command"):
                if key not in table:
                    raise BadInput(f"external_chains[{i}].{key}: required key missing")
            chain = ExternalChain(**table, here=str(here.resolve()))
        except BadInput as exc:
            raise BadInput(f"{where}: {exc}") from None
        out.append(ExternalChain(**{**table, "command": tuple(table["command"])},
                                 here=chain.here, files_sha256=_files_sha256(chain)))
    names = [c.name for c in out]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise BadInput(f"{where}: external_chains: duplicate name(s) {dup}")
    return tuple(out)
