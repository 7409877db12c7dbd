"""`radar-harness process` and `radar-harness simulate`: TI .cfg profiles and DCA1000 captures.

    radar-harness process CAPTURE.bin --cfg PROFILE.cfg [--out POINTS.parquet]
    radar-harness simulate CASE --cfg PROFILE.cfg --out capture.bin [--seed N] [--frames N]

`process` runs the signal chain (`pipeline.process_frame`) on every frame of a DCA1000 capture
recorded with the given profile, and the group tracker when it is available, and writes the
point cloud table (a `frame` and a `time_s` column in front of the chain's columns; Parquet or
CSV by the file suffix). The profile is read and turned into processing settings by
`harness.cell.ti_profile` (the same function a sweep cell with ``radar.profile`` uses): its
Doppler ``cfarCfg`` becomes the chain's CFAR, and every processing command takes its demo
family's meaning (a command left out, that demo's default).

`simulate` runs a scenario at the profile's frame rate (1 / ``framePeriodicity``, the period
`process` stamps the frames with), builds each frame's scatterers with the RCS model and writes
the front end's ADC frames for the profile's radar as a capture in the DCA1000 layout the
profile implies (`radarsim.capture.layout_of`: real or complex, ADC buffer interleaving), so
the same data can be replayed here or read by TI's and OpenRadar's readers. Random streams are
those of a sweep cell (``harness.sweep.streams.frame_rng(seed, frame, "rcs" | mimo)``), so a capture
of the R79 preset holds exactly the ADC frames a sweep of the same scenario and seed processes.
An advanced-frame profile's capture holds every sub-frame of each frame
(`write_subframe_capture`).
"""
from __future__ import annotations

import argparse
import contextlib
import dataclasses
import os
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from core.errors import BadInput, OutputError
from core.fileio import atomic_write
from harness.cell.ti_profile import (
    cfar_config_from_ti,
    load_profile,
    processing_from_profile,
    simulation_radar,
)
from harness.cli.args import (
    DURATION_S,
    FRAMES,
    LAYOUTS,
    MAX_FRAMES,
    SEED,
    add_capture_reading,
    add_plugin_option,
    check_output_file,
    int_in,
)

__all__ = ["add_arguments_process", "run_process", "add_arguments_simulate", "run_simulate",
           "write_subframe_capture",
           "cfar_config_from_ti", "processing_from_profile", "process_capture",
           "write_table", "TABLE_WRITERS"]

#: Output table formats by file suffix.
TABLE_WRITERS = {
    ".parquet": lambda df, path: df.to_parquet(path, index=False),
    ".csv": lambda df, path: df.to_csv(path, index=False),
}


# ---------------------------------------------------------------------------- helpers
@contextlib.contextmanager
def _naming(option: str):
    """An output that could not be written (a full disk, a read-only folder) named with the
    option that chose it: ``--out: cannot write '...': no space left on the device``."""
    try:
        yield
    except OutputError as exc:
        raise OutputError(f"{option}: {exc}") from None


def write_table(df: pd.DataFrame, path: str | os.PathLike) -> Path:
    """Write a table atomically (`core.fileio.atomic_write`: a full disk or read-only folder is
    an `core.errors.OutputError` naming `path`); the format follows the suffix
    (`TABLE_WRITERS`)."""
    path = Path(path)
    writer = TABLE_WRITERS.get(path.suffix.lower())
    if writer is None:
        raise BadInput(f"output {str(path)!r}: suffix {path.suffix!r} is not one of "
                       f"{sorted(TABLE_WRITERS)}")
    return atomic_write(path, lambda tmp: writer(df, tmp))


def process_capture(capture, profile, proc=None, *, interleaved: bool | None = None,
                    max_frames: int | None = None) -> pd.DataFrame:
    """Point cloud of every frame of a capture: `frame` (and `subframe` for an advanced-frame
    profile), `time_s`, then the chain's columns.

    Parameters
    ----------
    capture : path-like
        DCA1000 capture (`radarsim.capture` layout; sub-frames back to back,
        `radarsim.capture.subframes`).
    profile : radarsim.ti.TiProfile
        The profile it was recorded with (frame time = frame index x frame period + the
        sub-frame's start).
    proc : pipeline.ProcessingConfig or sequence of them, optional
        One per sub-frame (or one for all); default `processing_from_profile` of each.

    A profile's enabled ``calibDcRangeSig`` (`TiProfile.dc_range_signature`) runs as on the
    chip, per sub-frame: its first numAvg loops are measured and not compensated, every later
    chirp has the signature subtracted (`pipeline.dc_range_signature`).
    """
    import pipeline
    from radarsim.capture.subframes import iter_subframes

    if profile.is_joined:
        return _process_joined(capture, profile, proc, interleaved, max_frames)
    parts = profile.parts
    if proc is None:
        procs = [processing_from_profile(p) for p in parts]
    elif isinstance(proc, (list, tuple)):
        procs = list(proc)
    else:
        procs = [proc] * len(parts)
    tables = []
    calibrators = {k: _dc_calibrator(p) for k, p in enumerate(parts)}
    for sf in iter_subframes(capture, profile, interleaved=interleaved, max_frames=max_frames):
        part = parts[sf.subframe]
        frame_proc = _with_dc_signature(calibrators[sf.subframe], part.radar, sf.adc,
                                        procs[sf.subframe])
        pc = pipeline.process_frame(part.radar, sf.adc, frame_proc).reset_index(drop=True)
        pc.insert(0, "frame", np.full(len(pc), sf.frame, dtype=np.int64))
        if profile.is_advanced:
            pc.insert(1, "subframe", np.full(len(pc), sf.subframe, dtype=np.int64))
        pc.insert(pc.columns.get_loc("frame") + 1 + profile.is_advanced, "time_s",
                  np.full(len(pc), sf.frame * profile.frame_period_s + part.subframe_start_s))
        tables.append(pc)
    return pd.concat(tables, ignore_index=True)


def _dc_calibrator(part):
    """The chip's ``calibDcRangeSig`` calibration for one (sub-)frame profile, or None."""
    if part.dc_range_signature is None:
        return None
    from pipeline.dc_range_signature import DcSignatureCalibrator
    return DcSignatureCalibrator(*part.dc_range_signature)


def _with_dc_signature(calibrator, cfg, adc, proc):
    """`proc` with the DC range signature this frame gets (none while calibrating)."""
    if calibrator is None:
        return proc
    if calibrator.signature is None:
        from pipeline.chirp_level import range_stage
        sig = calibrator.process(range_stage(cfg, adc, proc))
    else:
        sig = calibrator.signature
    return proc if sig is None else proc.replace(**{"calibration.dc_range_signature": sig})


def _process_joined(capture, profile, proc, interleaved, max_frames) -> pd.DataFrame:
    """`process_capture` of a joined profile: each frame's sub-frame blocks, in order, are the
    chirps of one frame of `profile.radar`."""
    import pipeline
    from radarsim.capture.subframes import iter_subframes

    if isinstance(proc, (list, tuple)):
        proc = proc[0]
    proc = processing_from_profile(profile) if proc is None else proc
    n_parts = len(profile.parts)
    tables, blocks = [], []
    for sf in iter_subframes(capture, profile, interleaved=interleaved, max_frames=max_frames):
        blocks.append(sf.adc)
        if len(blocks) < n_parts:
            continue
        pc = pipeline.process_frame(profile.radar, np.concatenate(blocks), proc)
        pc = pc.reset_index(drop=True)
        blocks = []
        pc.insert(0, "frame", np.full(len(pc), sf.frame, dtype=np.int64))
        pc.insert(1, "time_s", np.full(len(pc), sf.frame * profile.frame_period_s))
        tables.append(pc)
    return pd.concat(tables, ignore_index=True)


def _track(points: pd.DataFrame, profile, n_frames: int) -> pd.DataFrame:
    """Tracks of the point cloud; an advanced frame's sub-frames are tracked separately (each
    sees its own range span and waveform) and the table gets a `subframe` column."""
    from pipeline import tracking as trk
    if profile.is_joined:  # one radar over its sub-frames: tracked as one frame
        profile = dataclasses.replace(profile, subframes=())
    tables = []
    for part in profile.parts:
        rows = points if not profile.is_advanced else \
            points[points["subframe"] == part.subframe_index].drop(columns=["subframe"])
        clouds = [(f * profile.frame_period_s + part.subframe_start_s,
                   rows[rows["frame"] == f].drop(columns=["frame", "time_s"])
                   .reset_index(drop=True)) for f in range(n_frames)]
        tracks = trk.track_frames(clouds, trk.TrackerConfig(
            motion=trk.MotionConfig(frame_period_s=profile.frame_period_s)))
        if profile.is_advanced:
            tracks.insert(1, "subframe", np.full(len(tracks), part.subframe_index, dtype=np.int64))
        tables.append(tracks)
    return pd.concat(tables, ignore_index=True) if len(tables) > 1 else tables[0]


def _layout_notes(layout: str, profile) -> list[str]:
    """A ``--layout`` that contradicts the profile's ``adcbufCfg`` ChanInterleave is obeyed
    (a recording made with another buffer setting) but said."""
    forced = LAYOUTS[layout]
    own = profile.radar.adcbuf_interleaved
    if forced is None or forced == own:
        return []
    line = profile.command_lines.get("adcbufCfg")
    said = (f"line {line} (adcbufCfg ChanInterleave={0 if own else 1})" if line else
            f"the {profile.radar.chip} demo's default (no adcbufCfg)")
    return [f"--layout {layout} contradicts {said}, which means "
            f"{'interleaved' if own else 'non-interleaved'}; the capture is read {layout}"]


# ---------------------------------------------------------------------------- process
def add_arguments_process(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("capture", type=Path,
                        help="DCA1000 capture (.bin, int16 words, real or complex ADC)")
    parser.add_argument("--cfg", type=Path, required=True,
                        help="TI .cfg profile, or the mmWave Studio LogFile / setup JSON it "
                             "was recorded with")
    parser.add_argument("--out", type=Path, default=None,
                        help="point cloud table, .parquet or .csv (default CAPTURE.parquet)")
    add_capture_reading(parser, "process")
    add_plugin_option(parser)
    parser.add_argument("--tracks", type=Path, default=None,
                        help="track table (default OUT with '_tracks' appended to the stem)")
    parser.add_argument("--no-track", action="store_true", help="do not run the tracker")
    parser.add_argument("--regroup-frames", type=int_in(2, MAX_FRAMES), default=None,
                        metavar="N", help="one-chirp-per-frame recordings (vital signs, "
                        "vibration): read N frames as one frame of N chirps at the frame "
                        "period (radarsim.capture.regroup)")


def _process_profile(args: argparse.Namespace):
    """(profile, regrouped frame count or None) of ``process``: the profile, or with
    ``--regroup-frames N`` the profile of N one-chirp frames as one (`radarsim.capture.regroup`);
    a one-chirp profile without the option is refused with a pointer to it."""
    from radarsim.capture import regroup as fr

    n = args.regroup_frames
    if n is None:
        try:
            one = Path(args.cfg).is_file() and fr.one_chirp_frames(Path(args.cfg))
        except (UnicodeDecodeError, OSError):
            one = False  # load_profile names the problem
        if one:
            raise BadInput(f"--cfg {str(args.cfg)!r} has one chirp per frame: give "
                           "--regroup-frames N to process N frames as one frame of N chirps")
        return load_profile(args.cfg), None
    if Path(args.cfg).is_dir():
        raise BadInput(f"--cfg {str(args.cfg)!r} is a directory, not a TI .cfg profile")
    profile = fr.regroup_profile(Path(args.cfg), n)
    return profile, fr.check_regroup(args.capture, profile.radar, n)


def run_process(args: argparse.Namespace) -> int:
    from radarsim.capture import capture_n_frames

    if args.frames is not None and args.frames < 1:
        raise BadInput(f"--frames={args.frames} must be >= 1")
    if args.capture.is_dir():
        raise BadInput(f"capture {str(args.capture)!r} is a directory, not a capture file")
    profile, _ = _process_profile(args)
    out = args.out if args.out is not None else args.capture.with_suffix(".parquet")
    if out.suffix.lower() not in TABLE_WRITERS:  # fail before the (long) processing
        raise BadInput(f"--out {str(out)!r}: suffix {out.suffix!r} is not one of "
                       f"{sorted(TABLE_WRITERS)}")
    check_output_file(out, "--out")
    if args.tracks is not None:
        check_output_file(args.tracks, "--tracks")
    if profile.is_advanced:
        from radarsim.capture.subframes import capture_n_advanced_frames
        n_frames = capture_n_advanced_frames(args.capture, profile)
    else:
        # Regrouped: check_regroup has checked that N divides the recorded frames.
        n_frames = capture_n_frames(args.capture, profile.radar)
    n_frames = n_frames if args.frames is None else min(n_frames, args.frames)
    procs = []
    for part in (profile,) if profile.is_joined else profile.parts:
        notes: list[str] = []
        procs.append(processing_from_profile(part, notes))
        notes += _layout_notes(args.layout, part)
        if profile.is_joined and any(p.dc_range_signature for p in profile.parts):
            notes.append("calibDcRangeSig is not applied to a fast/slow pair of sub-frames "
                         "processed as one frame")
        where = f"sub-frame {part.subframe_index}: " if part.subframe_index is not None else ""
        for note in notes:
            print(f"note: {where}{note}", file=sys.stderr)
    points = process_capture(args.capture, profile, procs,
                             interleaved=LAYOUTS[args.layout],
                             max_frames=n_frames)
    with _naming("--out"):
        write_table(points, out)
    print(f"{n_frames} frame(s), {len(points)} detection(s) -> {out}")
    if not args.no_track:
        tracks = _track(points, profile, n_frames)
        tpath = args.tracks or out.with_name(f"{out.stem}_tracks{out.suffix}")
        with _naming("--tracks" if args.tracks else "--out (its tracks table)"):
            write_table(tracks, tpath)
        print(f"{len(tracks)} track row(s) -> {tpath}")
    return 0


# ---------------------------------------------------------------------------- simulate
def add_arguments_simulate(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("case", help="scenario name (radar-harness scenarios lists them)")
    parser.add_argument("--cfg", type=Path, required=True,
                        help="TI .cfg profile, or an mmWave Studio LogFile / setup JSON")
    parser.add_argument("--out", type=Path, required=True, help="capture file to write (.bin)")
    parser.add_argument("--seed", type=SEED, default=0, help="scenario and noise seed")
    parser.add_argument("--frames", type=FRAMES, default=None, help="write at most N frames")
    parser.add_argument("--duration-s", type=DURATION_S, default=None,
                        help="scenario duration override, s")
    add_plugin_option(parser)


def _components():
    """The sweep runner's real parts (a seam for tests)."""
    from harness.cell.components import default_components
    return default_components()


def simulate_frames(cfg, run, seed: int, frames, comps):
    """ADC frames of a scenario run for radar `cfg`, as a sweep cell simulates them.

    Yields (n_chirps, n_rx, n_samples) int16 (real) or complex64 (complex ADC) per frame.
    """
    from harness.cell.run import frame_scatterers
    from harness.sweep.streams import frame_rng
    for f in frames:
        sc = frame_scatterers(comps, run, f, seed)
        yield comps.simulate_frame(cfg, sc, frame_rng(seed, f, cfg.mimo))


def write_subframe_capture(path, profile, run, seed: int, frames, comps) -> int:
    """Write an advanced-frame capture: per frame, every sub-frame's ADC block of the frame's
    scene (`radarsim.capture.subframes.encode_frame`), each sub-frame with its own random
    stream (``frame_rng(seed, frame, "<mimo>/subframe<k>")``); atomic. The sub-frames share the
    frame's scene (their start offsets within the frame, tens of ms, are not simulated).
    Returns the frame count."""
    from harness.cell.run import frame_scatterers
    from harness.sweep.streams import frame_rng
    from radarsim.capture.subframes import encode_frame

    def write(tmp) -> None:
        with open(tmp, "wb") as fh:
            for f in frames:
                sc = frame_scatterers(comps, run, f, seed)
                adcs = [comps.simulate_frame(p.radar, sc,
                                             frame_rng(seed, f, f"{p.radar.mimo}/subframe{k}"))
                        for k, p in enumerate(profile.parts)]
                fh.write(encode_frame(profile, adcs).tobytes())

    atomic_write(path, write)
    return len(frames)


def run_simulate(args: argparse.Namespace) -> int:
    from radarsim.capture import write_capture

    if args.seed < 0:
        raise BadInput(f"--seed={args.seed} must be >= 0")
    if args.frames is not None and args.frames < 1:
        raise BadInput(f"--frames={args.frames} must be >= 1")
    check_output_file(args.out, "--out")
    profile = load_profile(args.cfg)
    comps = _components()
    # The scenario advances one profile frame period per frame: process stamps frame f at
    # f x framePeriodicity, so the capture's scene must move by the same step.
    rate_hz = 1.0 / profile.frame_period_s
    try:
        run = comps.run_scenario(args.case, args.seed, args.duration_s, frame_rate_hz=rate_hz)
    except KeyError as exc:
        raise BadInput(f"unknown scenario {args.case!r}: {exc}") from exc
    src = run.ego if getattr(run, "ego", None) is not None and len(run.ego) else run.truth
    frames = np.unique(src["frame"].to_numpy())
    if args.frames is not None:
        frames = frames[:args.frames]
    from radarsim import ADCSaturationWarning
    with warnings.catch_warnings():
        # Saturation is a property of the scene (a car at 2 m), as in a sweep cell.
        warnings.simplefilter("ignore", category=ADCSaturationWarning)
        if profile.is_advanced:
            with _naming("--out"):
                n = write_subframe_capture(args.out, profile, run, args.seed, frames, comps)
            print(f"{n} frame(s) of {args.case} (seed {args.seed}, "
                  f"{len(profile.subframes)} sub-frames) -> {args.out}")
            return 0
        with _naming("--out"):
            n = write_capture(args.out, simulate_frames(simulation_radar(profile), run,
                                                        args.seed, frames, comps),
                              cfg=profile.radar)
    print(f"{n} frame(s) of {args.case} (seed {args.seed}) -> {args.out}")
    return 0
