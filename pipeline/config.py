"""Processing configuration of the signal chain: windows, CFAR, TDMA disambiguation."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any

from core.checks import one_of, require
from core.errors import BadInput

from .cfar import CfarConfig, default_os_rank
from .compensation import check_channel_comp, check_comp_values
from .dc_range_signature import DcRangeSignature
from .ege_format import ege_min_ratio
from .fov import FOV_FIELDS, check_interval
from .interference import INTF_THRESHOLD_MODES, MITIGATIONS, IntfThresholdMode
from .interference.residual import BLOCK
from .saturation import SATURATION_POLICIES

__all__ = ["CfarConfig", "ProcessingConfig", "WINDOWS", "INTF_THRESHOLD_MODES", "IntfThresholdMode",
           "default_os_rank"]

#: Windows by name (scipy.signal.get_window names).
WINDOWS = {"hann": "hann", "hamming": "hamming", "blackman": "blackman", "rect": "boxcar"}


@dataclass(frozen=True, kw_only=True, slots=True)
class ProcessingConfig:
    """Signal-chain settings shared by the DDMA chain and the TDMA baseline.

    Parameters
    ----------
    cfar : CfarConfig
        Doppler CFAR (on the Doppler-azimuth map for DDMA, on the non-coherent range-Doppler
        map for TDMA).
    range_window, doppler_window : str
        Window names, see `WINDOWS`.
    n_azimuth_bins : int
        Zero-padded azimuth FFT length (seed 000: 48).
    min_range_bin : int
        First range bin searched (bin 0 holds DC).
    tdma_disambiguation : bool
        TDMA and BPM (the slot-coded chains): resolve velocity beyond +/-Vmax by hypothesis
        testing (seed 001 section 4): each v_est + 2 k Vmax within +/- n_tx Vmax has its slot
        Doppler phase compensated (and, for BPM, is Hadamard-decoded) and is scored by the
        generalised likelihood of one echo on the whole virtual array, max over wx of
        (|A_h(wx)| + |A_v(wx)|)^2 (A_h, A_v: beams of the horizontal and the raised row;
        `pipeline.stages.array_likelihood`); without a raised row, by the horizontal
        azimuth-FFT peak. False: v_est as measured, aliased beyond +/-Vmax (the sweep's
        ``tdma_raw`` scheme).
    correct_range_doppler_coupling : bool
        Remove the fast-time Doppler shift f_D from the beat frequency (R += v c / (S lambda)).
    range_peak_check : bool
        Also require a local maximum along range (6-neighbour instead of the R79 demo's
        4-neighbour check). A strong echo's range-window skirt then yields one point, not one
        per range bin; two echoes in adjacent range bins at the same Doppler and azimuth merge.
    azimuth_sidelobe_db : float or None
        Keep a DDMA azimuth peak only if it is within this many dB of the strongest azimuth
        peak of its (range, Doppler) cell: rejects the -13 dB sidelobes of the unwindowed
        12-element array (TI's multi-object beamforming uses a 6 dB ratio). None disables it.
    dc_removal : bool
        Chirp-level chain (`chirp_level`, seed 004 section 2): subtract each chirp's and Rx's
        mean before the range FFT, as the R79 demo (default on).
    interference_mitigation : bool
        Flag samples by the HWA interference statistics and zero them before the window
        (``intfMitigCfg``; default on).
    intf_mag_snr_db, intf_magdiff_snr_db : float
        ``intfMitigCfg`` magSNRdB and magDiffSNRdB: thresholds over the chirp's mean |x| and
        mean |x_n - x_{n-1}|, amplitude dB (the demo profile: 15, 18), in (0, 60].
    intf_threshold_mode : str
        Which statistic flags a sample, see `INTF_THRESHOLD_MODES` (the demo: "magdiff").
    intf_hysteresis_samples : int
        Samples zeroed on each side of a flagged run (the demo's hysteresis order 3), 0..32.
    intf_mitigation : str
        How the flagged samples are repaired: a key of
        `pipeline.interference.MITIGATIONS`. Default "lowrank" (the gap predicted from
        the chirp's kept samples by the frame's fast-time signal subspace), chosen by the
        benchmark of issue 21 (`harness/sweeps/mitigation.toml`, README): on the head-on case
        it recovers 91 % (DDMA) / 94 % (TDMA) of the floor rise and adds no ghosts, where "ar"
        recovers 65 % / 69 % and adds 0.035 / 0.067, and the chip's "zero", whose slow-time
        modulation of every echo manufactures ghosts, 17 % / 20 % and adds 0.16 / 0.21.
    intf_weak_burst_snr_db : float or None
        Weak bursts the chip's fixed threshold misses (`pipeline.interference.residual`): in a
        frame where the chip flagged a chirp, a window of another chirp whose energy outside
        the frame's fast-time echo subspace exceeds the chirp's own level by this, dB, is
        flagged too, and repaired as the chip's flags are. Default 11 dB, in (0, 60]; None
        off (the chip's flags alone). On the head-on case the worst 1-second window's recovery
        goes from 0.47 (DDMA) / 0.56 (TDMA) to about 1.
    intf_weak_burst_window_samples : int
        Samples per window of that test, a multiple of 4 in [4, 128]; default 32 (1.07 us,
        the shortest burst of interest, 2 B_IF / |S_v - S_i| for 30 MHz/us).
    compression : bool
        EGE compression/decompression of the range-FFT cube (``compressionCfg``; default on).
    compression_ratio : float
        Compressed / raw size, in [0.25, 1) (the demo: 0.5); a radar also needs at least
        `ege_format.ege_min_ratio` for its block (0.32 for 4 Rx x 8 bins), which
        `check_radar` tests.
    compression_range_bins_per_block : int
        Range bins per block (blocks hold all Rx; the demo: 8), a power of 2 in 1..32.
    fast_slow_threshold_db : float
        Fast/slow unfolding (`pipeline.mimo.fast_slow`, seed 001 section 3 step 6): a
        candidate velocity survives if its slow-map peak is within this many dB of the fast
        peak, in (0, 20] dB (TI's SRR demo: 3 dB). Both sets carry the same energy, so the
        true candidate's ratio scatters about 0 dB.
    fast_slow_search_bins : int
        Half-width of the slow-map window searched around each candidate's aliased bin, 0..16
        (TI's SRR demo: 2); two candidates' windows must not overlap (`check_radar`).
    fast_slow_min_coherence : float
        Fast/slow unfolding: a candidate also needs this spatial coherence between the fast
        peak's and its slow peak's array samples (`pipeline.mimo.fast_slow.gate_coherence`), in
        [0, 1); 0 is the seed's power-only test. Default 0.2: another echo passes it with
        about 3.5 % probability, the true candidate at 3 dB per channel has about 0.44.
    fast_slow_keep_unassociated : bool
        Fast/slow unfolding: report a fast peak without an associated candidate at its aliased
        fast-set velocity (TI's SRR demo, "always allow the detections to go through"); False
        drops it (seed 001 step 8 gives no velocity for it).
    saturation_policy : {"flag", "drop"}
        What a frame with saturated ADC samples does to its detections
        (`pipeline.saturation`): "flag" keeps them with ``saturated = True``, "drop" removes
        them.
    range_bias_m : float
        ``compRangeBiasAndRxChanPhase`` rangeBias, m: subtracted from every reported range
        (`pipeline.compensation`; default 0).
    channel_comp : tuple of (re, im) or None
        ``compRangeBiasAndRxChanPhase`` coefficients, one per (Tx, Rx) pair of the chip in
        TI's chip channel order (Tx major), each part in [-1, 1] (Q15 when applied); every
        chain multiplies its virtual-antenna samples by them before angle estimation
        (`pipeline.compensation`). None: no correction (default).
    clutter_removal : bool
        TI's static clutter removal (``clutterRemoval``): the slot chains (TDMA, BPM) subtract
        each virtual channel's mean over the frame's chirps before the Doppler FFT, removing
        zero-Doppler returns (default off, as the demos).
    range_fov_m, velocity_fov_mps, azimuth_fov_deg, elevation_fov_deg : (min, max) or None
        Field of view of the reported detections (``cfarFovCfg`` range / Doppler,
        ``aoaFovCfg``): detections outside are dropped (`pipeline.fov`). None: no limit
        (default).
    dc_range_signature : pipeline.dc_range_signature.DcRangeSignature or None
        TI's DC range signature (``calibDcRangeSig``), subtracted from the range-FFT output
        of every chain (`pipeline.chirp_level.range_stage`); measured over a capture's first
        frames by ``radar-harness process``. None: nothing subtracted (default).
    """

    cfar: CfarConfig = field(default_factory=CfarConfig)
    range_window: str = "hann"
    doppler_window: str = "hann"
    n_azimuth_bins: int = 48
    min_range_bin: int = 1
    tdma_disambiguation: bool = True
    correct_range_doppler_coupling: bool = True
    range_peak_check: bool = True
    azimuth_sidelobe_db: float | None = 10.0
    dc_removal: bool = True
    interference_mitigation: bool = True
    intf_mag_snr_db: float = 15.0
    intf_magdiff_snr_db: float = 18.0
    intf_threshold_mode: str = "magdiff"
    intf_hysteresis_samples: int = 3
    intf_mitigation: str = "lowrank"
    intf_weak_burst_snr_db: float | None = 11.0
    intf_weak_burst_window_samples: int = 32
    compression: bool = True
    compression_ratio: float = 0.5
    compression_range_bins_per_block: int = 8
    saturation_policy: str = "flag"
    range_bias_m: float = 0.0
    channel_comp: tuple[tuple[float, float], ...] | None = None
    fast_slow_threshold_db: float = 3.0
    fast_slow_search_bins: int = 2
    fast_slow_min_coherence: float = 0.2
    fast_slow_keep_unassociated: bool = True
    clutter_removal: bool = False
    range_fov_m: tuple[float, float] | None = None
    velocity_fov_mps: tuple[float, float] | None = None
    azimuth_fov_deg: tuple[float, float] | None = None
    elevation_fov_deg: tuple[float, float] | None = None
    dc_range_signature: DcRangeSignature | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.cfar, CfarConfig):
            raise BadInput(f"cfar must be a CfarConfig, got {type(self.cfar).__name__}")
        one_of("range_window", self.range_window, WINDOWS)
        one_of("doppler_window", self.doppler_window, WINDOWS)
        require(self, "n_azimuth_bins", "integer", ge=16)
        require(self, "azimuth_sidelobe_db", gt=0, none_ok=True)
        require(self, "min_range_bin", "integer", ge=0)
        require(self, ("tdma_disambiguation", "correct_range_doppler_coupling",
                       "range_peak_check"), "bool")
        one_of("saturation_policy", self.saturation_policy, SATURATION_POLICIES)
        require(self, "fast_slow_threshold_db", gt=0, le=20, unit="dB")
        require(self, "fast_slow_search_bins", "integer", ge=0, le=16)
        require(self, "fast_slow_min_coherence", ge=0, lt=1)
        require(self, "fast_slow_keep_unassociated", "bool")

        require(self, ("dc_removal", "interference_mitigation", "compression",
                       "clutter_removal"), "bool")
        require(self, ("intf_mag_snr_db", "intf_magdiff_snr_db"), gt=0, le=60, unit="dB")
        one_of("intf_threshold_mode", self.intf_threshold_mode, INTF_THRESHOLD_MODES)
        one_of("intf_mitigation", self.intf_mitigation, MITIGATIONS)
        require(self, "intf_hysteresis_samples", "integer", ge=0, le=32)
        require(self, "intf_weak_burst_snr_db", gt=0, le=60, unit="dB", none_ok=True)
        require(self, "intf_weak_burst_window_samples", "integer", ge=BLOCK, le=128)
        if self.intf_weak_burst_window_samples % BLOCK:
            raise BadInput(f"intf_weak_burst_window_samples={self.intf_weak_burst_window_samples}"
                           f" must be a multiple of {BLOCK}")
        require(self, "compression_ratio", ge=0.25, lt=1)
        if self.dc_range_signature is not None:
            if not isinstance(self.dc_range_signature, DcRangeSignature):
                raise BadInput(f"dc_range_signature must be a DcRangeSignature or None, got "
                               f"{type(self.dc_range_signature).__name__}")
        object.__setattr__(self, "channel_comp",
                           check_comp_values(self.range_bias_m, self.channel_comp))
        for name in FOV_FIELDS:
            object.__setattr__(self, name, check_interval(name, getattr(self, name)))
        b = self.compression_range_bins_per_block
        if isinstance(b, bool) or not isinstance(b, int) or b not in (1, 2, 4, 8, 16, 32):
            raise BadInput(f"compression_range_bins_per_block={b!r} must be a power of 2 "
                           "in 1..32")

    def check_doppler_axis(self, n_doppler_bins: int) -> None:
        """Raise if the CFAR's cyclic window does not fit the Doppler axis of a radar.

        The training cells reach ``guard_cells + window_cells x training_stride`` bins to each
        side; both sides and the cell under test must fit in ``n_doppler_bins`` (DDMA: chirps
        per sub-band, TDMA: chirps per Tx), or the cyclic window would train on the cell itself.
        """
        c = self.cfar
        span = 2 * (c.guard_cells + c.window_cells * c.training_stride) + 1
        if span > n_doppler_bins:
            raise BadInput(f"cfar window_cells={c.window_cells} (guard_cells={c.guard_cells}, "
                           f"training_stride={c.training_stride}) spans {span} Doppler bins, "
                           f"more than the {n_doppler_bins} bins of the radar's Doppler axis")

    def check_compression(self, n_rx: int, n_range_bins: int) -> None:
        """Raise if EGE compression cannot run on a radar's range-FFT cube: the blocks must
        tile the range bins, and the ratio must leave room for the shortest EG code of the
        demo's k-array (`ege_format.ege_min_ratio`)."""
        if not self.compression:
            return
        b = self.compression_range_bins_per_block
        if n_range_bins % b:
            raise BadInput(f"compression_range_bins_per_block={b} does not divide the "
                           f"radar's {n_range_bins} range bins")
        lo = ege_min_ratio(n_rx, b)
        if self.compression_ratio < lo:
            raise BadInput(f"compression_ratio={self.compression_ratio:g} is below {lo:.4f}, "
                           f"the smallest a block of {n_rx} Rx x {b} range bins fits with "
                           "the demo's EG k-array (k >= 3: at least 5 bits per I/Q value)")

    def check_radar(self, cfg) -> None:
        """Raise if these settings cannot process `cfg`'s frames (`check_doppler_axis`,
        `check_compression`, the ``compRangeBiasAndRxChanPhase`` count of the chip,
        `check_search_width`): what a sweep checks for every cell before it starts."""
        self.check_doppler_axis(cfg.n_doppler_bins)
        self.check_compression(cfg.n_rx, cfg.n_range_bins)
        check_channel_comp(cfg, self.channel_comp)
        self.check_search_width(cfg.scheme.candidate_separation_bins(cfg))

    def check_search_width(self, separation_bins: float) -> None:
        """Raise if two velocity candidates' slow-map search windows (2 w + 1 bins each,
        ``fast_slow_search_bins`` = w) could overlap: a radar's candidates sit
        `separation_bins` apart (`radarsim.mimo.MimoScheme.candidate_separation_bins`; inf for
        schemes without a verifying map)."""
        w = self.fast_slow_search_bins
        if 2 * w + 1 > separation_bins:
            raise BadInput(f"fast_slow_search_bins={w}: the search window (2 x {w} + 1 bins) "
                           f"exceeds the {separation_bins:.3g} slow Doppler bins between two "
                           f"unfolding candidates of the radar (limit "
                           f"{int((separation_bins - 1) // 2)})")

    def replace(self, **changes: Any) -> "ProcessingConfig":
        """Copy with changes; `cfar_<field>` keys change the CFAR sub-config."""
        cfar_changes = {k[5:]: v for k, v in changes.items() if k.startswith("cfar_")}
        rest = {k: v for k, v in changes.items() if not k.startswith("cfar_")}
        names = {f.name for f in dataclasses.fields(self)}
        unknown = sorted(set(rest) - names)
        if unknown:
            raise BadInput(f"unknown ProcessingConfig field(s) {unknown}")
        if cfar_changes:
            rest["cfar"] = _replace_cfar(rest.get("cfar", self.cfar), cfar_changes)
        return dataclasses.replace(self, **rest)


def _replace_cfar(cfar: CfarConfig, changes: dict[str, Any]) -> CfarConfig:
    """`dataclasses.replace` of a CfarConfig that never keeps a stale OS rank.

    A new ``window_cells`` without an ``os_rank`` re-derives the default rank (3/4 N) when the
    old rank was the old default; an explicitly chosen rank is never carried over silently to
    another window: the caller must give ``os_rank`` too.
    """
    names = {f.name for f in dataclasses.fields(CfarConfig)}
    unknown = sorted(set(changes) - names)
    if unknown:
        raise BadInput(f"unknown CfarConfig field(s) {['cfar_' + u for u in unknown]}; known: "
                       f"{sorted('cfar_' + n for n in names)}")
    changes = dict(changes)
    if "window_cells" in changes and "os_rank" not in changes and \
            changes["window_cells"] != cfar.window_cells:
        if cfar.os_rank == default_os_rank(cfar.n_training):
            changes["os_rank"] = None
        else:
            raise BadInput(f"cfar_window_cells={changes['window_cells']!r} changes the training "
                           f"window, but os_rank={cfar.os_rank} was chosen for window_cells="
                           f"{cfar.window_cells}: give cfar_os_rank too (None: 3/4 of the "
                           "training cells)")
    return dataclasses.replace(cfar, **changes)
