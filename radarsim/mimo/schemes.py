"""MIMO transmit schemes: how the transmitters share a frame, as pluggable scheme objects.

A scheme owns everything scheme-specific on the transmit side: its validation rules on a
`RadarConfig`, the transmit code (who transmits with which sign and phase at each chirp, before
the shifter's static and random errors), the slow-time layout (sub-bands or slots), the
unambiguous velocity it promises and the step by which a wrong velocity resolution is off.
`MIMO_SCHEMES` maps the names users type (``RadarConfig.mimo``) to scheme objects; a new
scheme is one module with a `MimoScheme` subclass plus one `register_scheme` call, and the
receive side registers its chain in ``pipeline.MIMO_CHAINS`` under the same name.

References
----------
.. [1] TI, "AWR2944 DDMA waveform for corner radar" [TI-DDMA], section 3.2-3.3, tables 3-4.
.. [2] TI, "AWR1642 velocity disambiguation" [TI-VEXT], TDMA Vmax = lambda / (4 Nt Tc).
.. [3] TI, xwr16xx mmWave SDK user guide, ``bpmCfg`` (slow-time binary phase modulation).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, NamedTuple

import numpy as np

from core.errors import BadInput
from core.registry import Registry

__all__ = ["MimoScheme", "TransmitCode", "SlowTimeLayout", "TiFrame", "ChirpTiming",
           "MIMO_SCHEMES", "register_scheme", "scheme_of", "DdmaScheme", "TdmaScheme",
           "BpmScheme", "hadamard", "BPM_COLUMN_SIGNS", "BPM_BLIND_SHARE"]

#: A `radarsim.RadarConfig`: schemes read its fields and properties but do not import the
#: class (the config imports this module to validate and describe its scheme).
ConfigLike = Any


class TransmitCode(NamedTuple):
    """Ideal transmit code of a frame, before static and random shifter errors.

    Attributes
    ----------
    gain : (n_tx, n_chirps) float
        Amplitude and sign of each Tx at each chirp: 1 on, 0 silent, -1 sign-inverted (BPM).
    phase_rad : (n_tx, n_chirps) float
        Phase applied by each Tx's shifter at each chirp, rad (DDMA: the negated, possibly
        quantised programmed phase, [TI-DDMA] table 3-4).
    """

    gain: np.ndarray
    phase_rad: np.ndarray

    @property
    def weights(self) -> np.ndarray:
        """(n_tx, n_chirps) complex transmit weights gain x exp(j phase)."""
        return self.gain * np.exp(1j * self.phase_rad)


class SlowTimeLayout(NamedTuple):
    """How the transmitters share slow time.

    Attributes
    ----------
    n_groups : int
        Sub-bands (DDMA: Doppler sub-bands of the full spectrum) or slots per code period
        (TDMA, BPM: chirps of one cycle).
    group_of_tx : tuple of int
        Sub-band or slot position of Tx1..Tx{n_tx} (0-based), for DDMA the Doppler shift in
        sub-bands, for TDMA the slot the Tx fires in, for BPM the row of the code matrix.
    slow_time_period_s : float
        Sampling period of one transmitter's slow-time sequence after separation, s.
    n_doppler_bins : int
        Doppler bins per transmitter after separation.
    """

    n_groups: int
    group_of_tx: tuple[int, ...]
    slow_time_period_s: float
    n_doppler_bins: int


class ChirpTiming(NamedTuple):
    """When each chirp of a frame fires.

    Attributes
    ----------
    ramp_start_s : (n_chirps,) float
        Start of each chirp's ramp, s, the first at 0.
    t_c_s : (n_chirps,) float
        Each chirp's time relative to the frame's reference time (the middle of the burst), s:
        the slow time at which the echoes' two-way path is evaluated.
    """

    ramp_start_s: np.ndarray
    t_c_s: np.ndarray


class TiFrame(NamedTuple):
    """How a scheme is programmed with the TI mmWave SDK CLI.

    Attributes
    ----------
    chirps_per_loop : int
        Chirps of one ``frameCfg`` loop (chirpStartIdx..chirpEndIdx).
    chirp_lines : tuple of str
        ``chirpCfg`` commands of the loop.
    extra_lines : tuple of str
        Further scheme commands after ``frameCfg`` (``ddmPhaseShiftAntOrder``, ``bpmCfg``).
    repeatable : bool
        Whether a loop may hold the sequence several times (chirps k x chirps_per_loop + i
        as chirp i), as TI's demo profiles do when the frame needs more loops than the chip
        counts (xWR18xx occupancy-detection profile: Tx1, Tx3, Tx1, Tx3 x 128 loops).
    """

    chirps_per_loop: int
    chirp_lines: tuple[str, ...]
    extra_lines: tuple[str, ...] = ()
    repeatable: bool = False


@dataclass(frozen=True)
class MimoScheme:
    """Base of the transmit schemes; subclasses override the methods that differ.

    Attributes
    ----------
    name : str
        Registry key (`RadarConfig.mimo`, the results' ``scheme`` column).
    description : str
        One line for help texts and reports.
    """

    name: str
    description: str
    #: True if the scheme programs per-chirp Tx phases (chips without shifters cannot run it).
    needs_phase_shifter: ClassVar[bool] = False
    #: ADC frames the receiver needs before it reports an unfolded velocity (every scheme here
    #: unfolds within one frame; a frame-alternating fast/slow design, TI's TIDUF76, needs 2).
    latency_frames: ClassVar[int] = 1

    # ------------------------------------------------------------------ configuration
    def default_n_subbands(self, n_tx: int) -> int:
        """`RadarConfig.n_subbands` when not given (empty-band rule: Nt + 2 for Nt = 4, else
        Nt + 1; schemes without sub-bands keep it but ignore it)."""
        return n_tx + 2 if n_tx == 4 else n_tx + 1

    def default_tx_order(self, n_tx: int) -> tuple[int, ...]:
        """`RadarConfig.tx_order` when not given: horizontal Tx first (Tx1, Tx3, Tx4), the
        raised Tx2 last, as the R79 demo ([TI-DDMA] 3.3), restricted to the active Tx (a
        `RadarConfig` applies this rule to its board's geometry: lowest row first, raised
        last)."""
        return tuple(t for t in (1, 3, 4, 2) if t <= n_tx)

    def validate(self, cfg: ConfigLike) -> None:
        """Scheme rules on a config (called by `RadarConfig.__post_init__`).

        Raises
        ------
        ValueError
            Naming the field, its value and the limit.
        """

    def chirps_per_period(self, cfg: ConfigLike) -> int:
        """Chirps of one code period (the TI loop): n_chirps must be a multiple."""
        return cfg.n_tx

    def _check_divisible(self, cfg: ConfigLike, what: str) -> None:
        per = self.chirps_per_period(cfg)
        if cfg.n_chirps % per:
            raise BadInput(f"n_chirps={cfg.n_chirps} must be divisible by {what}={per} for "
                           f"{self.name.upper()}")

    # ------------------------------------------------------------------ transmit side
    def chirp_timing(self, cfg: ConfigLike) -> ChirpTiming:
        """Chirp start times of one frame: every chirp one `chirp_period_s` after the last
        (schemes with several chirp periods override this)."""
        c = np.arange(cfg.n_chirps)
        return ChirpTiming(c * cfg.chirp_period_s,
                           (c - (cfg.n_chirps - 1) / 2) * cfg.chirp_period_s)

    def transmit_code(self, cfg: ConfigLike) -> TransmitCode:
        """(n_tx, n_chirps) ideal transmit gains and phases of one frame."""
        raise NotImplementedError

    def layout(self, cfg: ConfigLike) -> SlowTimeLayout:
        """Slot / sub-band layout of the scheme."""
        raise NotImplementedError

    # ------------------------------------------------------------------ promises
    def slow_time_period_s(self, cfg: ConfigLike) -> float:
        """Sampling period of one Tx's slow-time sequence, s (TDMA, BPM: n_tx Tc)."""
        return cfg.chirp_period_s * cfg.n_tx

    def max_unambiguous_velocity_mps(self, cfg: ConfigLike) -> float:
        """lambda / (4 T) with T the slow-time period of one transmitter, m/s."""
        return cfg.wavelength_m / (4 * self.slow_time_period_s(cfg))

    def n_doppler_bins(self, cfg: ConfigLike) -> int:
        """Doppler bins per transmitter after separation."""
        return cfg.n_chirps // cfg.n_tx

    def candidate_separation_bins(self, cfg: ConfigLike) -> float:
        """Smallest distance, in Doppler bins of a verifying map, between two velocity
        candidates the receiver checks there (fast/slow: the slow map); inf for schemes
        without one. Bounds the receiver's search window."""
        return math.inf

    def velocity_resolution_mps(self, cfg: ConfigLike) -> float:
        """lambda / (2 T_frame): one Doppler bin of a sequence spanning the frame, m/s."""
        return cfg.wavelength_m / (2 * cfg.frame_time_s)

    def velocity_failure_step_mps(self, cfg: ConfigLike) -> float:
        """Step by which a wrong velocity resolution is off, m/s: one sub-band (DDMA) or the
        unambiguous span 2 Vmax of one transmitter's sequence (TDMA, BPM)."""
        return 2 * self.max_unambiguous_velocity_mps(cfg)

    def velocity_blind(self, cfg: ConfigLike, azimuth_deg, elevation_deg=0.0) -> np.ndarray:
        """Whether the scheme cannot resolve velocity beyond its Vmax for an echo from that
        direction (bool, the shape of the broadcast angles): never, unless a scheme says
        otherwise (`BpmScheme`)."""
        return np.zeros(np.broadcast(azimuth_deg, elevation_deg).shape, dtype=bool)

    # ------------------------------------------------------------------ TI CLI
    def to_ti(self, cfg: ConfigLike, n_tx_chip: int) -> TiFrame:
        """The ``chirpCfg``/``frameCfg`` loop and scheme commands of `cfg` (TI mmWave SDK).

        Raises
        ------
        ValueError
            If the scheme has no TI CLI form for this config.
        """
        raise BadInput(f"mimo={self.name!r} has no TI mmWave SDK CLI form")

    def from_ti(self, tx_masks: tuple[int, ...], n_tx: int, tx_mask: int,
                ddm_order: tuple[int, ...] | None) -> dict | None:
        """RadarConfig fields of a TI frame whose loop enables `tx_masks` (one bit mask per
        chirp), or None if the pattern is not this scheme's. The caller adds n_chirps.

        Parameters
        ----------
        tx_masks : tuple of int
            ``chirpCfg`` txEnable of each chirp of the loop.
        n_tx, tx_mask : int
            Active Tx (``channelCfg``) and their mask.
        ddm_order : tuple of int or None
            ``ddmPhaseShiftAntOrder`` (0-based TI Tx indices), if given.

        Raises
        ------
        ValueError
            If the pattern is the scheme's but incomplete (e.g. DDMA without an order).
        """
        return None


# ------------------------------------------------------------------------------ DDMA
@dataclass(frozen=True)
class DdmaScheme(MimoScheme):
    """Doppler-division MIMO: all Tx every chirp, Tx in sub-band p steps its phase by
    2 pi p / N per chirp ([TI-DDMA] section 3.3). With empty sub-bands (N > Nt) the
    demodulation resolves Tx and velocity over +/- lambda / (4 Tc) (table 11).

    Attributes
    ----------
    empty_band : bool
        True: N > Nt (at least one empty sub-band); False: classic DDMA, N = Nt.
    """

    empty_band: bool = True
    needs_phase_shifter: ClassVar[bool] = True

    def default_n_subbands(self, n_tx: int) -> int:
        return super().default_n_subbands(n_tx) if self.empty_band else n_tx

    def default_tx_order(self, n_tx: int) -> tuple[int, ...]:
        """Empty band: the R79 order. Classic DDMA: Tx1, Tx2, Tx3, Tx4 in sub-bands 0..3,
        the cyclic order whose wrong assignments the EVM array tells apart best: a model of
        the hypothesis test (noise-free array, 256-point likelihood grid, 4000 random targets
        over +/-60 deg azimuth, +/-15 deg elevation) fails 2.9 % at 20 dB detection SNR and
        0.5 % at 30 dB with it, against 13 % and 4.8 % with the R79 order (1, 3, 4, 2)."""
        return super().default_tx_order(n_tx) if self.empty_band else \
            tuple(range(1, n_tx + 1))

    def chirps_per_period(self, cfg: ConfigLike) -> int:
        return cfg.n_subbands

    def validate(self, cfg: ConfigLike) -> None:
        n_sb = cfg.n_subbands
        if self.empty_band:
            if not isinstance(n_sb, (int, np.integer)) or n_sb <= cfg.n_tx:
                raise BadInput(f"n_subbands={n_sb!r} must be an integer > n_tx={cfg.n_tx} "
                               "(empty-band DDMA needs at least one empty band)")
        elif n_sb != cfg.n_tx:
            raise BadInput(f"n_subbands={n_sb!r} must equal n_tx={cfg.n_tx} for "
                           f"{self.name} (classic DDMA: one sub-band per Tx, no empty band)")
        if cfg.n_chirps % n_sb:
            raise BadInput(f"n_chirps={cfg.n_chirps} must be divisible by the number of "
                           f"DDMA sub-bands n_subbands={n_sb}")

    def transmit_code(self, cfg: ConfigLike) -> TransmitCode:
        c = np.arange(cfg.n_chirps)
        phase = cfg.applied_phase_rad()[:, c % cfg.n_subbands]
        return TransmitCode(np.ones((cfg.n_tx, cfg.n_chirps)), phase)

    def layout(self, cfg: ConfigLike) -> SlowTimeLayout:
        return SlowTimeLayout(cfg.n_subbands, tuple(cfg.subband_of_tx[t]
                                                    for t in range(1, cfg.n_tx + 1)),
                              self.slow_time_period_s(cfg), self.n_doppler_bins(cfg))

    def slow_time_period_s(self, cfg: ConfigLike) -> float:
        return cfg.chirp_period_s * 1  # every Tx fires every chirp

    def n_doppler_bins(self, cfg: ConfigLike) -> int:
        return cfg.n_chirps // cfg.n_subbands

    def velocity_failure_step_mps(self, cfg: ConfigLike) -> float:
        return cfg.subband_width_mps

    def to_ti(self, cfg: ConfigLike, n_tx_chip: int) -> TiFrame:
        """One ``chirpCfg`` for the whole loop of N chirps with every Tx enabled, and the
        MCU+ SDK DDM demo's ``ddmPhaseShiftAntOrder`` (all chip Tx, active ones first)."""
        tx_mask = (1 << cfg.n_tx) - 1
        order = [t - 1 for t in cfg.tx_order]
        order += [t for t in range(n_tx_chip) if t not in order]
        return TiFrame(cfg.n_subbands,
                       (f"chirpCfg 0 {cfg.n_subbands - 1} 0 0 0 0 0 {tx_mask}",),
                       ("ddmPhaseShiftAntOrder " + " ".join(map(str, order)),))

    def from_ti(self, tx_masks, n_tx, tx_mask, ddm_order):
        per_loop = len(tx_masks)
        if not all(m == tx_mask for m in tx_masks) or (n_tx == 1 and ddm_order is None):
            return None
        if (per_loop > n_tx) != self.empty_band or per_loop < n_tx:
            return None
        if ddm_order is None:
            # The R79 firmware's hard-coded list has no ddmPhaseShiftAntOrder: its order is
            # the demo's (horizontal Tx first, raised last), the config's default.
            return {"mimo": self.name, "n_subbands": per_loop}
        return {"mimo": self.name, "n_subbands": per_loop,
                "tx_order": tuple(t + 1 for t in ddm_order if t < n_tx)}


# ------------------------------------------------------------------------------ TDMA
@dataclass(frozen=True)
class TdmaScheme(MimoScheme):
    """Time-division MIMO: one Tx per chirp, in turn (`tx_order` gives the slots), so each
    Tx samples slow time at n_tx Tc: Vmax = lambda / (4 Nt Tc) [TI-VEXT]."""

    def validate(self, cfg: ConfigLike) -> None:
        if cfg.n_chirps % cfg.n_tx:
            raise BadInput(f"n_chirps={cfg.n_chirps} must be divisible by n_tx={cfg.n_tx} "
                           "for TDMA")

    def transmit_code(self, cfg: ConfigLike) -> TransmitCode:
        c = np.arange(cfg.n_chirps)
        slot_tx = np.array(cfg.tx_order)[c % cfg.n_tx]  # 1-based Tx firing at chirp c
        on = (slot_tx[None, :] == np.arange(1, cfg.n_tx + 1)[:, None]).astype(float)
        return TransmitCode(on, np.zeros((cfg.n_tx, cfg.n_chirps)))

    def layout(self, cfg: ConfigLike) -> SlowTimeLayout:
        return SlowTimeLayout(cfg.n_tx, tuple(cfg.subband_of_tx[t]
                                              for t in range(1, cfg.n_tx + 1)),
                              self.slow_time_period_s(cfg), self.n_doppler_bins(cfg))

    def to_ti(self, cfg: ConfigLike, n_tx_chip: int) -> TiFrame:
        """One ``chirpCfg`` per slot enabling the slot's Tx."""
        return TiFrame(cfg.n_tx, tuple(f"chirpCfg {i} {i} 0 0 0 0 0 {1 << (t - 1)}"
                                       for i, t in enumerate(cfg.tx_order)), repeatable=True)

    def from_ti(self, tx_masks, n_tx, tx_mask, ddm_order):
        """One Tx per chirp; the loop repeats a sequence in which each Tx fires once (e.g.
        Tx1, Tx3, Tx1, Tx3 twice per loop: order Tx1, Tx3)."""
        single = [m.bit_length() - 1 if m & (m - 1) == 0 else None for m in tx_masks]
        first = single[:n_tx]
        if None in single or sorted(first) != list(range(n_tx)) or len(single) % n_tx or \
                any(t != first[i % n_tx] for i, t in enumerate(single)):
            return None
        return {"mimo": self.name, "tx_order": tuple(t + 1 for t in first)}


# ------------------------------------------------------------------------------ BPM
def hadamard(n: int) -> np.ndarray:
    """(n, n) Sylvester Hadamard matrix of +/-1 (n a power of 2): H H^T = n I.

    References
    ----------
    .. [1] J. J. Sylvester, "Thoughts on inverse orthogonal matrices", Phil. Mag. 34 (1867).
    """
    h = np.ones((1, 1))
    while h.shape[0] < n:
        h = np.block([[h, h], [h, -h]])
    return h


#: Column signs of the 4-Tx BPM code over the Sylvester matrix (`BpmScheme.code_matrix`):
#: Tx3 (code column 1) negated, so that no row of the code is the echo's transmit phase
#: vector at boresight.
BPM_COLUMN_SIGNS = (1, -1, 1, 1)
#: Share of an echo's transmit energy in one chirp of the BPM block from which the velocity
#: beyond +/-Vmax counts as unresolved (`BpmScheme.velocity_blind`): the other chirps carry
#: the phase that separates the hypotheses, and 10 % of the energy is 10 dB less SNR for it.
BPM_BLIND_SHARE = 0.9


@dataclass(frozen=True)
class BpmScheme(MimoScheme):
    """Slow-time binary phase modulation (BPM): all Tx every chirp, signs from an Nt x Nt
    Hadamard code C over blocks of Nt chirps (TI xwr16xx SDK ``bpmCfg``: 2 Tx with (+,+),
    (+,-); 4 Tx: `code_matrix`). Chirp s of a block carries C[s, i] on Tx `tx_order[i]`;
    the receiver decodes x = C^T y / Nt after removing the Doppler phase of each chirp of the
    block, so each Tx keeps the full transmit energy (gain 10 log10 Nt over TDMA) and
    Vmax = lambda / (4 Nt Tc), as TDMA.

    Velocity beyond +/-Vmax and the code. Hypotheses k apart leave the per-chirp residual
    r_s = exp(j pi k s / 2) (Nt = 4): the decoded array is C^T diag(r) C x / Nt. Whether any
    score can reject a wrong k at an azimuth depends on the echo's transmit superposition
    C e, e_i the phase of Tx `tx_order[i]` towards the target: when e is proportional to a ROW
    of C, only one chirp of each block carries the echo, slow time is sampled at Nt Tc and
    every hypothesis fits equally (a blind azimuth). With the Sylvester matrix (all rows of
    even parity) the R79 array is blind at boresight, e = (1, 1, 1, 1): the wrong hypothesis
    k = 2 is a pure permutation of the Tx channels. Negating Tx3's column (`BPM_COLUMN_SIGNS`)
    makes every row odd: at boresight the echo spreads over all four chirps and a wrong
    hypothesis explains at most 66 % of the array's energy within +/-3 deg (TDMA: 84 % at
    every angle).

    Limit: every 4 x 4 Hadamard code is Sylvester's up to row and column permutations and
    signs, so its rows all share one parity, and the R79 array's e is (1, 1, 1, 1) at
    sin(az) = 0 or +/-1 and (1, 1, 1, -1) at sin(az) = +/-1/2 (elevation 0): some azimuth is
    blind for every code. This code puts it at +/-30 deg (elevation 0; a wrong hypothesis
    fits better than 93 % within about +/-3 deg of it) instead of boresight. Detections there
    may carry a velocity off by a multiple of 2 Vmax, which the metrics count as velocity-
    resolution failures (`velocity_failure_step_mps`); `velocity_blind` names such
    directions and the unfolding benchmark flags its 30 deg row with it. A 2-Tx code (TI's)
    is blind wherever the two Tx are in phase or in antiphase, boresight included: extension
    beyond +/-Vmax with 2-Tx BPM is unreliable there.
    """

    def validate(self, cfg: ConfigLike) -> None:
        if cfg.n_tx & (cfg.n_tx - 1):
            raise BadInput(f"n_tx={cfg.n_tx} must be a power of 2 (1, 2, 4) for BPM "
                           "(Hadamard code of Nt chirps)")
        if cfg.n_chirps % cfg.n_tx:
            raise BadInput(f"n_chirps={cfg.n_chirps} must be divisible by n_tx={cfg.n_tx} "
                           "for BPM (whole Hadamard blocks)")

    def code_matrix(self, cfg: ConfigLike) -> np.ndarray:
        """(n_tx, n_tx) signs: row = chirp of the block, column = position in `tx_order`.
        The Sylvester matrix with `BPM_COLUMN_SIGNS` for 4 Tx (class docstring: boresight is
        not blind), TI's (+,+), (+,-) for 2 Tx."""
        h = hadamard(cfg.n_tx)
        return h * np.asarray(BPM_COLUMN_SIGNS) if cfg.n_tx == 4 else h

    def velocity_blind(self, cfg: ConfigLike, azimuth_deg, elevation_deg=0.0) -> np.ndarray:
        """Directions where the code leaves velocity beyond +/-Vmax unresolved: the echo's
        transmit superposition C e (class docstring) puts at least `BPM_BLIND_SHARE` of its
        energy in one chirp of the block (R79: 28-32 deg at elevation 0; exactly one chirp
        at 30 deg), so at most a tenth carries the intra-block phase that tells the
        hypotheses apart.

        Examples
        --------
        >>> import radarsim
        >>> cfg = radarsim.presets.r79("bpm")
        >>> cfg.scheme.velocity_blind(cfg, [0.0, 1.0, 29.0, 30.0, -30.0, 45.0]).tolist()
        [False, False, True, True, True, False]
        """
        az, el = np.broadcast_arrays(np.radians(np.asarray(azimuth_deg, dtype=float)),
                                     np.radians(np.asarray(elevation_deg, dtype=float)))
        u = np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], axis=-1)
        pos = cfg.tx_positions_m[np.array(cfg.tx_order) - 1]  # (n_tx, 3)
        e = np.exp(2j * np.pi / cfg.wavelength_m * (u @ pos.T))  # (..., n_tx)
        p = np.abs(e @ self.code_matrix(cfg).T) ** 2  # (..., n_tx) energy per chirp
        return p.max(axis=-1) >= BPM_BLIND_SHARE * p.sum(axis=-1)

    def to_ti(self, cfg: ConfigLike, n_tx_chip: int) -> TiFrame:
        """TI's SDK BPM (xwr16xx/18xx/68xx demos): two chirps enabling both Tx and
        ``bpmCfg -1 1 0 1`` (chirp 0: +,+; chirp 1: +,- on the lower, higher Tx)."""
        if cfg.n_tx != 2 or cfg.tx_order != (1, 2):
            raise BadInput(f"mimo={self.name!r} with n_tx={cfg.n_tx}, tx_order="
                           f"{cfg.tx_order} has no TI mmWave SDK CLI form (TI's bpmCfg codes "
                           "two Tx in order (1, 2) only)")
        return TiFrame(2, ("chirpCfg 0 1 0 0 0 0 0 3",), ("bpmCfg -1 1 0 1",))

    def transmit_code(self, cfg: ConfigLike) -> TransmitCode:
        h = self.code_matrix(cfg)
        slot = np.arange(cfg.n_chirps) % cfg.n_tx
        gain = np.empty((cfg.n_tx, cfg.n_chirps))
        gain[np.array(cfg.tx_order) - 1] = h[slot].T  # row i of h[slot].T: position i
        return TransmitCode(gain, np.zeros((cfg.n_tx, cfg.n_chirps)))

    def layout(self, cfg: ConfigLike) -> SlowTimeLayout:
        return SlowTimeLayout(cfg.n_tx, tuple(cfg.subband_of_tx[t]
                                              for t in range(1, cfg.n_tx + 1)),
                              self.slow_time_period_s(cfg), self.n_doppler_bins(cfg))


#: Registry of MIMO schemes by the name users type (`RadarConfig.mimo`).
MIMO_SCHEMES: Registry[MimoScheme] = Registry("scheme", field="mimo", kind=MimoScheme,
                                              identifier=True)


def register_scheme(scheme: MimoScheme, *, replace: bool = False) -> MimoScheme:
    """Add a scheme to `MIMO_SCHEMES` under `scheme.name` and return it.

    Raises
    ------
    ValueError
        If the name is taken (and `replace` is False) or not a non-empty identifier.

    Examples
    --------
    >>> import radarsim
    >>> from radarsim.mimo import MIMO_SCHEMES, TdmaScheme
    >>> class ReversedTdma(TdmaScheme):
    ...     def default_tx_order(self, n_tx):
    ...         return tuple(range(n_tx, 0, -1))
    >>> radarsim.register_scheme(ReversedTdma("tdma_reversed", "TDMA, last Tx first")).name
    'tdma_reversed'
    >>> radarsim.presets.r79("tdma_reversed").tx_order
    (4, 3, 2, 1)
    >>> _ = MIMO_SCHEMES.unregister("tdma_reversed")
    """
    return MIMO_SCHEMES.register(scheme, replace=replace)


def scheme_of(name: str) -> MimoScheme:
    """The registered scheme called `name`.

    Raises
    ------
    ValueError
        Naming the unknown value and the registered names.

    Examples
    --------
    >>> from radarsim.mimo import scheme_of
    >>> scheme_of("ddma").needs_phase_shifter
    True
    >>> scheme_of("fdma")
    Traceback (most recent call last):
    ...
    core.errors.BadInput: mimo='fdma' is not one of [...]
    """
    return MIMO_SCHEMES.lookup(name)


register_scheme(DdmaScheme("ddma", "Doppler-division: all Tx every chirp, per-Tx phase step, "
                                   "empty sub-bands"))
register_scheme(TdmaScheme("tdma", "time-division: one Tx per chirp, in turn"))
register_scheme(BpmScheme("bpm", "slow-time Hadamard (BPM): all Tx every chirp, signs from an "
                                 "Nt x Nt Hadamard code over blocks of Nt chirps"))
register_scheme(DdmaScheme("ddma_classic", "classic DDMA: N = Nt sub-bands, no empty band; "
                                           "Tx assignment resolved by hypothesis testing",
                           empty_band=False))
