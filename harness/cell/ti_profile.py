"""A TI profile as the harness runs it: the ONE place a profile becomes a `RadarConfig` and
`ProcessingConfig` settings, for `radar-harness process` and for a sweep cell with
``radar.profile`` alike (same file, same configs).

`profile_processing` gives the `ProcessingConfig` overrides the profile defines (its demo
family's meaning of every processing command, `radarsim.ti.families`; its Doppler ``cfarCfg``
as the chain's CFAR); `processing_from_profile` applies them to the defaults; `load_profile`
reads a file once (cached by path, size and modification time).
"""
from __future__ import annotations

import dataclasses
import functools
import os
from pathlib import Path

from core.errors import BadInput
from core.fileio import check_input_file

__all__ = ["load_profile", "profile_processing", "processing_from_profile",
           "cfar_config_from_ti", "simulation_radar", "sweep_profile_notes"]


def cfar_config_from_ti(ti_cfar):
    """`pipeline.CfarConfig` from a TI ``cfarCfg`` (`radarsim.ti.TiCfar`).

    averageMode -> mode (CA, CAGO, CASO: the TDM demos' log-magnitude statistic,
    `pipeline.cfar.log_law`; OS as is), one-sided winLen/guardLen -> window_cells/guard_cells,
    osKvalue -> os_rank (OS only), thresholdScale (dB of that statistic over the noise
    estimate) -> threshold_db (so the design Pfa is not used). TI's fixed-point noise divisor
    has no counterpart (the demos set it to the window's log2: a mean).
    """
    import pipeline
    from pipeline.cfar import ti_log_mode
    return pipeline.CfarConfig(mode=ti_log_mode(ti_cfar.mode),
                               guard_cells=int(ti_cfar.guard_cells),
                               window_cells=int(ti_cfar.window_cells),
                               os_rank=int(ti_cfar.os_rank)
                               if pipeline.CFAR_MODES[ti_cfar.mode].ranked else None,
                               pfa=None, threshold_db=float(ti_cfar.threshold_db))


def profile_processing(profile, notes: list[str] | None = None) -> dict:
    """`ProcessingConfig` overrides a TI profile (or one sub-frame of it) defines.

    Parameters
    ----------
    profile : radarsim.ti.TiProfile
    notes : list of str, optional
        Receives a note for each setting the chain cannot follow (range CFAR, non-cyclic
        Doppler CFAR, a contiguous CFAR training window on a short Doppler axis).

    Returns
    -------
    dict
        Dotted keys for `pipeline.ProcessingConfig.replace` (``cfar`` a `CfarConfig`).
    """
    import pipeline
    notes = [] if notes is None else notes
    # What the profile asks for that the chain does not do: read but not modelled (one line),
    # another demo family's commands, syntaxes kept and ignored.
    notes += [n for n in profile.notes if n.startswith("read but not modelled: ")
              or " is not a command of the " in n or n.endswith(" ignored")]
    overrides = pipeline.config_keys.dotted_keys(profile.processing)
    _multi_peak_note(profile, notes)
    doppler = profile.cfar.get("doppler")
    if "range" in profile.cfar:
        notes.append(f"line {profile.cfar['range'].line_no}: range cfarCfg ignored (the chain "
                     "has no range CFAR, design.md section 5)")
    if doppler is not None:
        if not doppler.cyclic:
            notes.append(f"line {doppler.line_no}: cyclicMode 0 ignored (the Doppler CFAR is "
                         "cyclic)")
        overrides["cfar"] = cfar_config_from_ti(doppler)
    proc = pipeline.ProcessingConfig().replace(**overrides)
    n_dop = profile.radar.n_doppler_bins
    try:
        proc.check_doppler_axis(n_dop)
    except ValueError:
        # Demo profiles of 16 loops have 16 Doppler bins: train on contiguous cells (TI's
        # CFAR) when the stride-2 window does not fit; if that does not fit either, the
        # chain names the window and the axis.
        overrides["cfar"] = dataclasses.replace(proc.cfar, training_stride=1)
        notes.append(f"CFAR training_stride 1 (contiguous cells, as TI's CFAR): the stride-2 "
                     f"window does not fit the {n_dop} Doppler bins")
    return overrides


def _multi_peak_note(profile, notes: list[str]) -> None:
    """An enabled ``multiObjBeamForming`` on a chain that reports one azimuth peak per cell
    (`pipeline.MimoChain.multi_azimuth_peaks`): its second peak is read but not modelled."""
    import pipeline
    from radarsim.ti.processing_handlers import ONE_PEAK_DB
    line = profile.command_lines.get("multiObjBeamForming")
    if line is None or "azimuth_sidelobe_db" not in profile.processing:
        return
    if profile.processing["azimuth_sidelobe_db"] == ONE_PEAK_DB:
        return
    chain = pipeline.MIMO_CHAINS.get(profile.radar.mimo)
    if chain is None or chain.multi_azimuth_peaks:
        return
    item = (f"line {line} multiObjBeamForming enabled (the {profile.radar.mimo} chain reports "
            "the strongest azimuth peak of each range-Doppler cell only)")
    head = "read but not modelled: "
    at = [i for i, n in enumerate(notes) if n.startswith(head)]
    if at:  # one line lists every command read but not modelled
        notes[at[0]] = f"{notes[at[0]]}; {item}"
    else:
        notes.append(head + item)


def sweep_profile_notes(profile) -> list[str]:
    """What a sweep cell with ``radar.profile`` does not do of what the profile asks: the notes
    `profile_processing` gives (the same as `radar-harness process` prints) plus the
    capture-level ``calibDcRangeSig``, which `process` runs over a capture's first frames and a
    cell, which simulates a front end without a DC range signature, does not."""
    notes: list[str] = []
    profile_processing(profile, notes)
    if any(p.dc_range_signature for p in profile.parts):
        notes.append("calibDcRangeSig not applied in a sweep cell (a calibration over a "
                     "capture's first frames: `radar-harness process` applies it)")
    return notes


def simulation_radar(profile):
    """The radar `simulate` and a sweep cell build for a profile: its `RadarConfig` on the board its
    ``compRangeBiasAndRxChanPhase`` line calibrates (`pipeline.compensation.implied_board`:
    e.g. the antiphase Rx of antenna-on-package boards, whose demo profiles carry
    ``1 0 -1 0 ...``), so that `process` with the same profile, which applies the line, sees
    the targets where they are. A profile without the line: its radar unchanged."""
    from pipeline.compensation import implied_board
    proc = profile.processing
    board = implied_board(profile.radar, proc.get("channel_comp"), proc.get("range_bias_m", 0.0))
    return profile.radar.replace_fields(**board) if board else profile.radar


def processing_from_profile(profile, notes: list[str] | None = None):
    """`pipeline.ProcessingConfig` of a TI profile: the defaults with `profile_processing`.

    Raises
    ------
    ValueError
        If the profile's compression settings cannot run on its radar.
    """
    import pipeline
    proc = pipeline.ProcessingConfig().replace(**profile_processing(profile, notes))
    proc.check_compression(profile.radar.n_rx, profile.radar.n_range_bins)
    return proc


@functools.lru_cache(maxsize=32)
def _cached(path: str, size: int, mtime_ns: int):
    from radarsim.ti import parse_setup
    return parse_setup(Path(path))


def load_profile(path: str | os.PathLike):
    """The `radarsim.ti.TiProfile` of a profile file (read once per file version): a TI CLI
    profile, an mmWave Studio LogFile or setup JSON (`radarsim.ti.parse_setup`).

    Raises
    ------
    ValueError
        If the path is a directory or the profile is bad (naming the line).
    FileNotFoundError
        If the file does not exist.
    """
    p = Path(path)
    if p.is_dir():
        raise BadInput(f"--cfg {str(p)!r} is a directory, not a TI .cfg profile")
    if not os.path.lexists(p):
        raise BadInput(f"TI .cfg file {str(p)!r} not found")
    if not p.is_file():  # a FIFO, device, socket or link loop: named (core.fileio)
        check_input_file(p, "--cfg")
    st = p.stat()
    return _cached(str(p.resolve()), st.st_size, st.st_mtime_ns)
