"""ADC frame to point cloud: dispatch to the receive chain of the frame's MIMO scheme.

Each scheme's chain lives in its own module of `pipeline.mimo` (empty-band DDMA of TI's R79
demo, the TDMA baseline, ...) and shares the common stages of `pipeline.stages` (range FFT,
Doppler FFT, CFAR, interpolation, angle estimation). `process_frame` looks the chain up in
`MIMO_CHAINS` by `cfg.mimo`; nothing here knows a scheme by name.

`snr_db` is the detection's peak power in the coherent (range, Doppler, azimuth) spectrum over
the mean noise power of that spectrum, estimated by the CFAR and converted from its order
statistic to a mean (`cfar.noise_mean_factor`), so all schemes' values compare directly.
"""
from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

import numpy as np
import pandas as pd

from core.errors import BadInput
from radarsim.config import RadarConfig

from . import saturation
from .chirp_level import idle_mitigation
from .config import ProcessingConfig
from .fov import apply_fov
from .mimo import MIMO_CHAINS, MimoChain, chain_of
from .stages import POINT_CLOUD_COLUMNS, check_frame

__all__ = ["process_frame", "process_frames", "frame_spectra", "detection_map",
           "doppler_azimuth_map",
           "MIMO_CHAINS", "POINT_CLOUD_COLUMNS"]


def _inputs(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig | None):
    """Checked inputs: (chain, proc, saturation report). The saturation monitor runs first
    and also refuses a frame with non-finite samples (complex ADC), so no chain ever sees
    one."""
    report = _checked_frame(cfg, adc)
    return (*_checked_processing(cfg, proc), report)


def _checked_frame(cfg: RadarConfig, adc: np.ndarray) -> saturation.SaturationReport:
    """The frame checked against `cfg` and its saturation report."""
    check_frame(cfg, adc)
    return saturation.monitor(adc)


def _checked_processing(cfg: RadarConfig, proc: ProcessingConfig | None
                        ) -> tuple[MimoChain, ProcessingConfig]:
    """The chain of `cfg` and the settings (None: the default) checked against both."""
    proc = _default_processing() if proc is None else proc
    if not isinstance(proc, ProcessingConfig):
        raise BadInput(f"proc must be a pipeline.ProcessingConfig, got {type(proc).__name__}")
    chain = chain_of(cfg)
    proc.check_radar(cfg)
    if proc.doppler.clutter_removal and not chain.removes_static_clutter:
        raise BadInput(f"clutter_removal=True: the {cfg.mimo} chain has no static clutter "
                       "removal (TI's clutterRemoval belongs to the TDM/BPM demos)")
    return chain, proc


@lru_cache(maxsize=1)
def _default_processing() -> ProcessingConfig:
    """`ProcessingConfig()`, built once: a frozen config, so every frame without settings can
    share it (building one validates every field: ~0.15 ms inside a frame)."""
    return ProcessingConfig()


def process_frame(cfg: RadarConfig, adc: np.ndarray,
                  proc: ProcessingConfig | None = None) -> pd.DataFrame:
    """Turn one ADC frame into a point cloud.

    Parameters
    ----------
    cfg : radarsim.RadarConfig
        The radar that produced the frame (`cfg.mimo` selects the chain in `MIMO_CHAINS`).
    adc : (n_chirps, n_rx, n_samples) int16, or complex64 for a complex ADC mode
        ADC samples (`RadarConfig.adc_dtype`).
    proc : ProcessingConfig, optional
        Windows, CFAR and disambiguation settings; default `ProcessingConfig()`.

    Returns
    -------
    pandas.DataFrame
        One row per detection, radar frame: range_m, azimuth_deg, elevation_deg,
        radial_velocity_mps (negative = approaching), snr_db, x_m, y_m, z_m, range_bin,
        doppler_bin (0..n_chirps-1 in the full unambiguous Doppler span), azimuth_bin, and
        ``saturated`` with ``attrs["saturation"]``: ADC saturation per chirp and Rx
        (`pipeline.saturation`; ``proc.saturation_policy`` flags or drops the detections of a
        saturated frame); only detections inside the field of view ``proc`` sets
        (`pipeline.fov`).

    Raises
    ------
    ValueError
        If `adc` is not an array of the config's dtype and shape or holds non-finite samples
        (complex ADC; the message gives their count and the first one's chirp, Rx and
        sample), `cfg`/`proc` are of the wrong type, no chain is registered for `cfg.mimo`, or
        the CFAR window does not fit the Doppler axis.

    Examples
    --------
    >>> import numpy as np, pipeline, radarsim
    >>> cfg = radarsim.presets.r79_ddma()
    >>> car = radarsim.Scatterers.from_spherical([30.0], [10.0], [0.0], [-5.0], [10.0])
    >>> adc = radarsim.simulate_frame(cfg, car, np.random.default_rng(0))
    >>> pc = pipeline.process_frame(cfg, adc)
    >>> best = pc.loc[pc["snr_db"].idxmax()]
    >>> bool(abs(best["range_m"] - 30.0) < cfg.range_resolution_m)
    True
    >>> bool(abs(best["radial_velocity_mps"] + 5.0) < cfg.velocity_resolution_mps)
    True
    >>> bool(abs(best["azimuth_deg"] - 10.0) < 4.8)    # half the 12-element resolution
    True
    """
    chain, proc, report = _inputs(cfg, adc, proc)
    return _completed(chain.process(cfg, adc, proc), chain, proc, report)


def process_frames(cfg: RadarConfig, adc: np.ndarray,
                   procs: Sequence[ProcessingConfig | None]) -> list[pd.DataFrame]:
    """`process_frame` of one frame under several processing settings, in order: the same
    point clouds, with the stages the settings have in common computed once where the chain
    shares them (`MimoChain.process_variants`; TDMA and ``tdma_raw`` share everything up to
    the velocity hypotheses). Equal settings, and settings that differ only in interference
    mitigation that has nothing to repair in this frame (`_cloud_sources`), are processed
    once; each entry still gets a cloud of its own.

    Parameters
    ----------
    cfg, adc
        As `process_frame`.
    procs : sequence of ProcessingConfig or None
        One point cloud per entry (None: `ProcessingConfig()`).

    Returns
    -------
    list of pandas.DataFrame
        ``process_frame(cfg, adc, proc)`` for each entry.
    """
    report = _checked_frame(cfg, adc)
    checked = [_checked_processing(cfg, proc) for proc in procs]
    if not checked:
        return []
    chain = checked[0][0]
    settings = [proc for _, proc in checked]
    source = _cloud_sources(adc, settings, chain.mitigation_in_range_stage)
    runs = list(dict.fromkeys(source))
    raw = dict(zip(runs, chain.process_variants(cfg, adc, [settings[i] for i in runs])))
    # completion works in place: a cloud that serves several settings is copied for each
    # further one before any is completed
    clouds, taken = [], set()
    for i in source:
        clouds.append(raw[i].copy() if i in taken else raw[i])
        taken.add(i)
    return [_completed(pc, chain, proc, report) for pc, proc in zip(clouds, settings)]


def _cloud_sources(adc: np.ndarray, settings: list[ProcessingConfig],
                   idle_shares: bool) -> list[int]:
    """For each setting, the index of the setting whose cloud it takes on this frame: the
    first setting equal to it, or, for a chain whose interference settings act through the
    range stage alone (`idle_shares`, `MimoChain.mitigation_in_range_stage`) and where the
    mitigation has nothing to repair here (`chirp_level.idle_mitigation`), the first one that
    gives the same cloud without mitigation (an interference case's mitigation reference,
    ``proc.unmitigated``). The frame's statistics are read only for settings that could
    share a cloud that way."""
    source = [settings.index(proc) for proc in settings]
    if not idle_shares:
        return source
    classes: dict[ProcessingConfig, list[int]] = {}
    for i, proc in enumerate(settings):
        classes.setdefault(proc.unmitigated, []).append(i)
    for members in classes.values():
        distinct = {settings[i] for i in members}
        if len(distinct) > 1:
            # the frame's statistics once per distinct setting with mitigation on; the others
            # give the unmitigated cloud by definition
            idle = {p: idle_mitigation(adc, p) for p in distinct if p.interference.enabled}
            plain = [i for i in members if idle.get(settings[i], True)]
            for i in plain:
                source[i] = plain[0]
    return source


def _completed(points: pd.DataFrame, chain: MimoChain, proc: ProcessingConfig,
               report: saturation.SaturationReport) -> pd.DataFrame:
    """A chain's point cloud with the saturation policy and the field of view applied."""
    points = saturation.apply_policy(points, report, proc.saturation_policy, owned=True)
    return apply_fov(points, proc.fov, chain.fov_fields)


def detection_map(cfg: RadarConfig, adc: np.ndarray,
                  proc: ProcessingConfig | None = None) -> tuple[np.ndarray, int, int]:
    """The square-law map the CFAR runs on, for tests of the detector and for plots.

    Returns
    -------
    `pipeline.mimo.DetectionMap` (power, looks, cfar_axis)
        DDMA: (n_range, n_azimuth, n_doppler) coherent Doppler-azimuth maps after empty-band
        demodulation, 1 look; TDMA: (n_range, n_doppler) non-coherent sum over virtual
        antennas, n_virtual looks; the (cyclic) Doppler axis the CFAR runs along.
    """
    chain, proc, _ = _inputs(cfg, adc, proc)
    return chain.detection_map(cfg, adc, proc)


def doppler_azimuth_map(cfg: RadarConfig, adc: np.ndarray, range_bin: int,
                        proc: ProcessingConfig | None = None):
    """Doppler-azimuth power of one range bin, as the chain sees it, for plots.

    DDMA: the demodulated coherent map the CFAR runs on, each Doppler bin at its unwrapped
    velocity (Tx1's sub-band, table 11). TDMA: per-slot Doppler spectrum with the later slots'
    Doppler phase compensated at each bin's own (unaliased-hypothesis) velocity, then the same
    zero-padded azimuth DFT.

    Returns
    -------
    velocity_mps : (n_dop,) float, ascending
    sin_az_cos_el : (n_az,) float, ascending (2 k / n_az, k = -n_az/2 .. n_az/2 - 1)
    power_db : (n_dop, n_az) float
    """
    chain, proc, _ = _inputs(cfg, adc, proc)
    if not 0 <= range_bin < cfg.n_range_bins:
        raise BadInput(f"range_bin={range_bin} outside 0..{cfg.n_range_bins - 1}")
    n_az = proc.angle.n_azimuth_bins
    vel, power = chain.doppler_azimuth(cfg, adc, range_bin, proc)
    order = np.argsort(vel)
    power = np.fft.fftshift(power[order], axes=1)
    sin_az = 2 * (np.arange(n_az) - n_az // 2) / n_az
    return vel[order], sin_az, 10 * np.log10(np.maximum(power, 1e-30))


def frame_spectra(cfg: RadarConfig, adc: np.ndarray,
                  proc: ProcessingConfig | None = None) -> dict[str, np.ndarray]:
    """Range-Doppler map of a frame for plots and tests.

    Returns
    -------
    dict
        "range_doppler_db": (n_range, n_doppler) power summed over channels, dB, with Doppler
        in natural FFT order over the chain's slow-time sequence (DDMA: all chirps, before
        demodulation; TDMA: per-slot Doppler).
    """
    chain, proc, _ = _inputs(cfg, adc, proc)
    p = chain.range_doppler_power(cfg, adc, proc)
    return {"range_doppler_db": 10 * np.log10(np.maximum(p, 1e-30))}
