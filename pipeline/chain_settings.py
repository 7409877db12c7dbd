"""The small settings of the chains' own stages, each a frozen dataclass that validates itself:
the range and Doppler FFTs (`RangeConfig`, `DopplerConfig`, read by `pipeline.stages`, the
range stage `pipeline.chirp_level` and the chains), the azimuth FFT (`AngleConfig`) and the
velocity disambiguation of the slot-coded and fast/slow chains (`VelocityConfig`, read by
`pipeline.mimo`). `pipeline.ProcessingConfig` holds one of each."""
from __future__ import annotations

from dataclasses import dataclass

from core.checks import one_of, require

__all__ = ["WINDOWS", "RangeConfig", "DopplerConfig", "AngleConfig", "VelocityConfig"]

#: Windows by name (scipy.signal.get_window names).
WINDOWS = {"hann": "hann", "hamming": "hamming", "blackman": "blackman", "rect": "boxcar"}


@dataclass(frozen=True, kw_only=True, slots=True)
class RangeConfig:
    """Range FFT and range detection.

    Parameters
    ----------
    window : str
        Range window name, see `WINDOWS`.
    dc_removal : bool
        Chirp-level chain (`pipeline.chirp_level`, [TI-DAZ] section 2): subtract each chirp's
        and Rx's mean before the range FFT, as the R79 demo (default on).
    min_bin : int
        First range bin searched (bin 0 holds DC).
    peak_check : bool
        Also require a local maximum along range (6-neighbour instead of the R79 demo's
        4-neighbour check). A strong echo's range-window skirt then yields one point, not one
        per range bin; two echoes in adjacent range bins at the same Doppler and azimuth merge.
    doppler_coupling_correction : bool
        Remove the fast-time Doppler shift f_D from the beat frequency (R += v c / (S lambda)).
    """

    window: str = "hann"
    dc_removal: bool = True
    min_bin: int = 1
    peak_check: bool = True
    doppler_coupling_correction: bool = True

    def __post_init__(self) -> None:
        one_of("window", self.window, WINDOWS)
        require(self, "min_bin", "integer", ge=0)
        require(self, ("dc_removal", "peak_check", "doppler_coupling_correction"), "bool")


@dataclass(frozen=True, kw_only=True, slots=True)
class DopplerConfig:
    """Doppler FFT.

    Parameters
    ----------
    window : str
        Doppler window name, see `WINDOWS`.
    clutter_removal : bool
        TI's static clutter removal (``clutterRemoval``): the slot chains (TDMA, BPM) subtract
        each virtual channel's mean over the frame's chirps before the Doppler FFT, removing
        zero-Doppler returns (default off, as the demos).
    """

    window: str = "hann"
    clutter_removal: bool = False

    def __post_init__(self) -> None:
        one_of("window", self.window, WINDOWS)
        require(self, "clutter_removal", "bool")


@dataclass(frozen=True, kw_only=True, slots=True)
class AngleConfig:
    """Azimuth estimation.

    Parameters
    ----------
    n_azimuth_bins : int
        Zero-padded azimuth FFT length ([TI-DDMA]: 48), at least 16.
    azimuth_sidelobe_db : float or None
        Keep a DDMA azimuth peak only if it is within this many dB of the strongest azimuth
        peak of its (range, Doppler) cell: rejects the -13 dB sidelobes of the unwindowed
        12-element array (TI's multi-object beamforming uses a 6 dB ratio). None disables it.
    """

    n_azimuth_bins: int = 48
    azimuth_sidelobe_db: float | None = 10.0

    def __post_init__(self) -> None:
        require(self, "n_azimuth_bins", "integer", ge=16)
        require(self, "azimuth_sidelobe_db", gt=0, none_ok=True)


@dataclass(frozen=True, kw_only=True, slots=True)
class VelocityConfig:
    """Velocity disambiguation beyond +/-Vmax.

    Parameters
    ----------
    tdma_disambiguation : bool
        TDMA and BPM (the slot-coded chains): resolve velocity beyond +/-Vmax by hypothesis
        testing ([TI-VEXT] section 4): each v_est + 2 k Vmax within +/- n_tx Vmax has its slot
        Doppler phase compensated (and, for BPM, is Hadamard-decoded) and is scored by the
        generalised likelihood of one echo on the whole virtual array, max over wx of
        (|A_h(wx)| + |A_v(wx)|)^2 (A_h, A_v: beams of the horizontal and the raised row;
        `pipeline.stages.array_likelihood`); without a raised row, by the horizontal
        azimuth-FFT peak. False: v_est as measured, aliased beyond +/-Vmax (the sweep's
        ``tdma_raw`` scheme).
    fast_slow_threshold_db : float
        Fast/slow unfolding (`pipeline.mimo.fast_slow`, [TI-VEXT] section 3 step 6): a
        candidate velocity survives if its slow-map peak is within this many dB of the fast
        peak, in (0, 20] dB (TI's SRR demo: 3 dB). Both sets carry the same energy, so the
        true candidate's ratio scatters about 0 dB.
    fast_slow_search_bins : int
        Half-width of the slow-map window searched around each candidate's aliased bin, 0..16
        (TI's SRR demo: 2); two candidates' windows must not overlap
        (`pipeline.ProcessingConfig.check_radar`).
    fast_slow_min_coherence : float
        A candidate also needs this spatial coherence between the fast peak's and its slow
        peak's array samples (`pipeline.mimo.fast_slow.gate_coherence`), in [0, 1); 0 is the
        seed's power-only test. Default 0.2: another echo passes it with about 3.5 %
        probability, the true candidate at 3 dB per channel has about 0.44.
    fast_slow_keep_unassociated : bool
        Report a fast peak without an associated candidate at its aliased fast-set velocity
        (TI's SRR demo, "always allow the detections to go through"); False drops it ([TI-VEXT]
        step 8 gives no velocity for it).
    """

    tdma_disambiguation: bool = True
    fast_slow_threshold_db: float = 3.0
    fast_slow_search_bins: int = 2
    fast_slow_min_coherence: float = 0.2
    fast_slow_keep_unassociated: bool = True

    def __post_init__(self) -> None:
        require(self, ("tdma_disambiguation", "fast_slow_keep_unassociated"), "bool")
        require(self, "fast_slow_threshold_db", gt=0, le=20, unit="dB")
        require(self, "fast_slow_search_bins", "integer", ge=0, le=16)
        require(self, "fast_slow_min_coherence", ge=0, lt=1)
