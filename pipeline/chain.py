"""ADC frame to point cloud: the empty-band DDMA chain of TI's R79 demo and a TDMA baseline.

DDMA (seed 000 section 5): range FFT -> Doppler FFT over all chirps -> empty-band demodulation
(cyclic sub-band sum, table 11), which both separates the transmitters and unwraps the velocity
over +/-lambda/(4 Tc) -> zero-padded azimuth FFT of the 12 horizontal virtual antennas ->
Doppler-azimuth map per range bin -> OS-CFAR along Doppler (cyclic) and a 4-neighbour local
maximum (figure 19) -> azimuth interpolation (table 14) and elevation (table 15).

TDMA (seed 001): range FFT -> Doppler FFT per transmitter slot (n_chirps / n_tx chirps at
n_tx Tc) -> CFAR on the non-coherent range-Doppler map summed over the virtual antennas ->
Doppler-phase compensation of later slots (eq. 8-10) -> velocity disambiguation by hypothesis
testing over v_est + 2 k Vmax (section 4): the hypothesis whose compensation gives the largest
azimuth-FFT peak wins -> the same angle estimation as DDMA.

`snr_db` is the detection's peak power in the coherent (range, Doppler, azimuth) spectrum over
the mean noise power of that spectrum, estimated by the CFAR and converted from its order
statistic to a mean (`cfar.noise_mean_factor`), so DDMA and TDMA values compare directly.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
import pandas as pd

from radarsim.config import C_MPS, RadarConfig

from .cfar import noise_mean_factor
from .config import WINDOWS, ProcessingConfig
from .kernels import (array_layout, candidate_cfar, ddma_metric, doppler_fft,
                      estimate_angles, local_max_mask, parabolic_offset, range_fft, window)

__all__ = ["process_frame", "frame_spectra", "detection_map", "doppler_azimuth_map",
           "MIMO_CHAINS", "POINT_CLOUD_COLUMNS"]

#: Columns of every point cloud, in order.
POINT_CLOUD_COLUMNS = ["range_m", "azimuth_deg", "elevation_deg", "radial_velocity_mps",
                       "snr_db", "x_m", "y_m", "z_m", "range_bin", "doppler_bin",
                       "azimuth_bin"]


def _check_frame(cfg: RadarConfig, adc: np.ndarray) -> None:
    if not isinstance(cfg, RadarConfig):
        raise ValueError(f"cfg must be a radarsim.RadarConfig, got {type(cfg).__name__}")
    if not isinstance(adc, np.ndarray):
        raise ValueError(f"adc must be a numpy.ndarray, got {type(adc).__name__}")
    if adc.dtype != cfg.adc_dtype:
        raise ValueError(f"adc dtype must be {cfg.adc_dtype} ({cfg.adc_mode} ADC samples), got "
                         f"{adc.dtype}")
    want = (cfg.n_chirps, cfg.n_rx, cfg.n_samples)
    if adc.shape != want:
        raise ValueError(f"adc shape {adc.shape} does not match the config "
                         f"(n_chirps, n_rx, n_samples) = {want}")


def _power(x: np.ndarray, consume: bool = False) -> np.ndarray:
    """|x|^2 of a C-contiguous complex64 array as float32 (re^2 + im^2 on the float32 view,
    without the square root of np.abs); `consume=True` squares x's memory in place."""
    v = x.view(np.float32)
    v = np.square(v, out=v) if consume else np.square(v)
    return v[..., 0::2] + v[..., 1::2]


def _log(p: np.ndarray) -> np.ndarray:
    return np.log(np.maximum(p, 1e-30))


def _point_cloud(cfg: RadarConfig, proc: ProcessingConfig, range_pos: np.ndarray,
                 velocity: np.ndarray, az: np.ndarray, el: np.ndarray, snr_db: np.ndarray,
                 bins: dict[str, np.ndarray]) -> pd.DataFrame:
    rng_m = range_pos * cfg.range_resolution_m
    if proc.correct_range_doppler_coupling:
        # f_beat = 2 S R / c + f_D with f_D = -2 v / lambda: undo the Doppler shift.
        rng_m = rng_m + velocity * C_MPS / (cfg.slope_hz_per_s * cfg.wavelength_m)
    order = np.lexsort((bins["azimuth_bin"], bins["doppler_bin"], bins["range_bin"]))
    rng_m, velocity, az, el, snr_db = (x[order] for x in (rng_m, velocity, az, el, snr_db))
    bins = {k: v[order] for k, v in bins.items()}
    cos_el = np.cos(el)
    df = pd.DataFrame({
        "range_m": rng_m,
        "azimuth_deg": np.degrees(az),
        "elevation_deg": np.degrees(el),
        "radial_velocity_mps": velocity,
        "snr_db": snr_db,
        "x_m": rng_m * cos_el * np.cos(az),
        "y_m": rng_m * cos_el * np.sin(az),
        "z_m": rng_m * np.sin(el),
        **bins,
    })
    return df


def _interp_azimuth(power_az: np.ndarray, a: np.ndarray) -> np.ndarray:
    """wx / pi from the azimuth bin of each peak and its cyclic neighbours.

    power_az : (n, n_fft) float; a : (n,) int -> (n,) sin(az) cos(el)."""
    n_fft = power_az.shape[-1]
    rows = np.arange(a.size)
    y = _log(power_az)
    off = parabolic_offset(y[rows, (a - 1) % n_fft], y[rows, a], y[rows, (a + 1) % n_fft])
    k = a + off
    k = np.where(k >= n_fft / 2, k - n_fft, k)  # table 14 step 4: mirror to [-N/2, N/2)
    return 2.0 * k / n_fft


def _interp_range(power_r: np.ndarray, r: np.ndarray, n_range: int) -> np.ndarray:
    """Fractional range bin from the log power at r-1, r, r+1 (edges not interpolated).

    power_r : (n, 3) float for bins r-1, r, r+1."""
    y = _log(power_r)
    off = parabolic_offset(y[:, 0], y[:, 1], y[:, 2])
    off = np.where((r <= 0) | (r >= n_range - 1), 0.0, off)
    return r + off


# --------------------------------------------------------------------------------------- DDMA
@lru_cache(maxsize=16)
def _array_dft(cfg: RadarConfig, n_fft: int, row: str) -> np.ndarray:
    """(n_virtual, n_fft) complex64 zero-padded DFT of one row of the virtual array as a
    matrix, so `samples @ W` is the row's n_fft-point azimuth spectrum: element m at horizontal
    position p (lambda/2 units) of the row gets exp(-2j pi p k / n_fft), every other element
    zero. row: "horizontal" (the z = 0 row) or "raised" (Tx2's row)."""
    h_idx, h_pos, v_idx, v_pos, _ = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    idx, pos = (h_idx, h_pos) if row == "horizontal" else (v_idx, v_pos)
    w = np.zeros((cfg.n_virtual, n_fft), dtype=np.complex64)
    w[idx] = np.exp(-2j * np.pi * np.outer(pos, np.arange(n_fft)) / n_fft)
    w.setflags(write=False)
    return w


@lru_cache(maxsize=8)
def _row_offsets(n_rx: int, n_range: int, n_chirps: int) -> np.ndarray:
    """(n_rx, n_range, 1) int32 flat offset of each (Rx, range) row of a (B, R, C) spectrum."""
    rows = np.arange(n_range, dtype=np.int32)[None, :, None] * n_rx + \
        np.arange(n_rx, dtype=np.int32)[:, None, None]
    return rows * np.int32(n_chirps)


def _ddma_maps(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> dict:
    """Range FFT, Doppler FFT, empty-band demodulation and the coherent detection map.

    Returns a dict with "power" (n_az, n_range, n_dop) float32 Doppler-azimuth maps (Doppler
    last, so the CFAR runs along contiguous memory), "spec" (n_range, n_rx, n_chirps)
    complex64 Doppler spectra before demodulation, "energy" (n_range, n_chirps) their
    Rx-summed energy and "tx1_band" (n_dop, n_range) int, the sub-band of the first Tx of
    `tx_order` (seed 000 table 11)."""
    n_sb, n_tx, n_rx = cfg.n_subbands, cfg.n_tx, cfg.n_rx
    n_chirps = cfg.n_chirps
    n_dop = n_chirps // n_sb
    n_az = proc.n_azimuth_bins
    rf = range_fft(adc, window(WINDOWS[proc.range_window], cfg.n_samples))  # (C, R, B)
    n_range = rf.shape[-1]
    # Slow time last and contiguous for the Doppler FFT and the demodulation gather.
    spec = doppler_fft(np.ascontiguousarray(rf.transpose(2, 1, 0)),
                       window(WINDOWS[proc.doppler_window], n_chirps), axis=-1)  # (B, R, C)
    energy = _power(spec).sum(axis=1)  # (B, C), summed over Rx
    tx1_band = np.argmax(ddma_metric(energy.T, n_sb, n_tx), axis=0)  # (D, B)
    # Demodulation: Tx p of Doppler bin d sits at chirp-bin d + n_dop (band + p) mod N. Only
    # the transmitters of the horizontal row enter the azimuth map; one flat take gathers them
    # straight into the (p, rx, range, Doppler) layout of the GEMM below.
    h_idx, *_ = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    tx_h = np.unique(h_idx // n_rx).astype(np.int32)  # sub-band positions p of the row
    band = (tx1_band.T[None] + tx_h[:, None, None]) % n_sb  # (P_h, B, D)
    col = band * n_dop + np.arange(n_dop, dtype=np.int32)
    flat = _row_offsets(n_rx, n_range, n_chirps)[None] + col[:, None]  # (P_h, R, B, D)
    virt_h = spec.reshape(-1)[flat.reshape(-1)].reshape(tx_h.size * n_rx, n_range * n_dop)
    # Zero-padded azimuth FFT over the horizontal row as one complex GEMM.
    rows = (tx_h[:, None] * n_rx + np.arange(n_rx)).reshape(-1)
    az_spec = _array_dft(cfg, n_az, "horizontal")[rows].T @ virt_h  # (A, B*D)
    power = _power(az_spec, consume=True).reshape(n_az, n_range, n_dop)
    return {"power": power, "spec": spec, "energy": energy, "tx1_band": tx1_band}


def _ddma_virtual(cfg: RadarConfig, spec: np.ndarray, tx1_band: np.ndarray, r: np.ndarray,
                  d: np.ndarray) -> np.ndarray:
    """(n, n_virtual) demodulated virtual-antenna samples at range bins r, Doppler bins d, in
    the order Tx1Rx1..Rx4, Tx3.., Tx4.., Tx2.. (seed 000 section 5.4)."""
    n_dop = cfg.n_chirps // cfg.n_subbands
    band = (tx1_band[d, r][:, None] + np.arange(cfg.n_tx)) % cfg.n_subbands  # (n, P)
    chirp_bin = band * n_dop + d[:, None]
    return spec[r[:, None, None], np.arange(cfg.n_rx)[None, None, :],
                chirp_bin[:, :, None]].reshape(r.size, -1)


def _ddma(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> pd.DataFrame:
    maps = _ddma_maps(cfg, adc, proc)
    power, energy, tx1_band = maps["power"], maps["energy"], maps["tx1_band"]
    n_az, n_range, n_dop = power.shape
    n_tx = cfg.n_tx
    cf = proc.cfar
    alpha = cf.scale(looks=1)
    if cf.mode == "os":
        # Exact necessary condition: the k-th smallest of a subset of the Doppler column is
        # >= the k-th smallest of the whole column, so alpha x that bounds the threshold.
        col_k = np.partition(power, cf.os_rank - 1, axis=2)[:, :, cf.os_rank - 1: cf.os_rank]
        pre = power > alpha * col_k
    else:
        pre = np.ones(power.shape, dtype=bool)
    pre[:, : proc.min_range_bin] = False
    # Figure 19: 4-neighbour maximum in (azimuth, Doppler), optionally also along range.
    local_max_mask(power, {0: True, 1: False, 2: True} if proc.range_peak_check
                   else {0: True, 2: True}, mask=pre)
    cand = np.unravel_index(np.flatnonzero(pre), power.shape)
    noise = candidate_cfar(power, cand, 2, cf.guard_cells, cf.window_cells, cf.mode,
                           cf.os_rank, cf.training_stride)
    peak = power[cand]
    hit = peak > alpha * noise
    a, r, d = (c[hit] for c in cand)
    noise, peak = noise[hit], peak[hit]
    if proc.azimuth_sidelobe_db is not None:
        strongest = power[:, r, d].max(axis=0)
        keep = peak >= strongest * 10 ** (-proc.azimuth_sidelobe_db / 10)
        a, r, d, noise, peak = a[keep], r[keep], d[keep], noise[keep], peak[keep]
    if r.size == 0:
        return pd.DataFrame({c: pd.Series(dtype=float) for c in POINT_CLOUD_COLUMNS})

    # Range: interpolate on the coherent map at the same (Doppler, azimuth) cell.
    pr = power[a[:, None], np.clip(r[:, None] + np.arange(-1, 2), 0, n_range - 1), d[:, None]]
    range_pos = _interp_range(pr, r, n_range)
    # Doppler: true bin d + n_dop x (Tx1 band); interpolate on the Rx-summed energy of all Tx.
    k_true = d + n_dop * tx1_band[d, r]
    offs = (k_true[:, None, None] + np.arange(-1, 2)[None, :, None]
            + n_dop * np.arange(n_tx)[None, None, :]) % cfg.n_chirps
    y = _log(energy[r[:, None, None], offs].sum(axis=-1))  # (n, 3)
    k_frac = k_true + parabolic_offset(y[:, 0], y[:, 1], y[:, 2])
    k_signed = (k_frac + cfg.n_chirps / 2) % cfg.n_chirps - cfg.n_chirps / 2
    velocity = -k_signed / (cfg.n_chirps * cfg.chirp_period_s) * cfg.wavelength_m / 2
    # Angles.
    h_idx, h_pos, v_idx, v_pos, v_h = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    sin_term = _interp_azimuth(power[:, r, d].T, a)
    virt = _ddma_virtual(cfg, maps["spec"], tx1_band, r, d)
    az, el = estimate_angles(virt, sin_term, h_idx, h_pos, v_idx, v_pos, v_h)
    noise_mean = noise / noise_mean_factor(cf.mode, cf.n_training, cf.os_rank, 1)
    snr_db = 10 * np.log10(peak / noise_mean)
    return _point_cloud(cfg, proc, range_pos, velocity, az, el, snr_db,
                        {"range_bin": r, "doppler_bin": k_true % cfg.n_chirps,
                         "azimuth_bin": a})


# --------------------------------------------------------------------------------------- TDMA
def _tdma_maps(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> dict:
    """Range and per-slot Doppler FFT; "power" is the (n_range, n_dop) non-coherent map
    summed over the virtual antennas, "virt" (n_range, n_dop, n_virtual) slot-major samples."""
    n_tx = cfg.n_tx
    n_dop = cfg.n_chirps // n_tx
    rf = range_fft(adc, window(WINDOWS[proc.range_window], cfg.n_samples))  # (C, R, B)
    rf = rf.reshape(n_dop, n_tx, cfg.n_rx, -1)  # chirp = n_tx c' + slot
    spec = doppler_fft(rf, window(WINDOWS[proc.doppler_window], n_dop))  # (D, S, R, B)
    n_range = spec.shape[-1]
    virt_all = np.moveaxis(spec, 3, 0).reshape(n_range, n_dop, -1)  # (B, D, 16) slot-major
    rd = (np.abs(virt_all) ** 2).sum(axis=-1)  # (B, D), L = n_virtual looks per cell
    return {"power": rd, "virt": virt_all}


def _tdma_hypothesis_score(cfg: RadarConfig, virt: np.ndarray, az_pow: np.ndarray,
                           h_idx: np.ndarray, h_pos: np.ndarray, v_idx: np.ndarray,
                           v_pos: np.ndarray) -> np.ndarray:
    """Likelihood of each velocity hypothesis after its Doppler-phase compensation, (n, H).

    The generalised likelihood of one echo on the whole virtual array, max over (wx, wz) of
    |a(wx, wz)^H x|^2: with wz free, the maximum over wz of |A_h(wx) + A_v(wx) e^{-j wz}|^2 is
    (|A_h(wx)| + |A_v(wx)|)^2, A_h and A_v the zero-padded beams of the horizontal and the
    raised row on the same wx grid. A wrong hypothesis leaves a staircase of slot phases that
    the horizontal row can largely mistake for an angle shift (its Tx groups are four elements
    apart), but the raised row (one slot) then peaks elsewhere, so the sum loses. Without a
    raised row this is the horizontal FFT peak of seed 001 section 4.

    virt : (n, H, n_virtual) compensated samples, slot-major; az_pow : (n, H, n_az) |A_h|^2.
    """
    if v_idx.size == 0:
        return az_pow.max(axis=-1)
    n_az = az_pow.shape[-1]
    a_v = np.abs(virt @ _array_dft(cfg, n_az, "raised"))  # (n, H, A)
    return ((np.sqrt(az_pow) + a_v) ** 2).max(axis=-1)


def _tdma(cfg: RadarConfig, adc: np.ndarray, proc: ProcessingConfig) -> pd.DataFrame:
    n_tx = cfg.n_tx
    n_dop = cfg.n_chirps // n_tx
    n_az = proc.n_azimuth_bins
    maps = _tdma_maps(cfg, adc, proc)
    rd, virt_all = maps["power"], maps["virt"]
    n_range = rd.shape[0]

    cf = proc.cfar
    looks = cfg.n_virtual
    alpha = cf.scale(looks=looks)
    cand_mask = local_max_mask(rd, {0: False, 1: True} if proc.range_peak_check else {1: True})
    cand_mask[: proc.min_range_bin] = False
    cand = np.nonzero(cand_mask)
    noise = candidate_cfar(rd, cand, 1, cf.guard_cells, cf.window_cells, cf.mode, cf.os_rank,
                           cf.training_stride)
    hit = rd[cand] > alpha * noise
    r, d = (c[hit] for c in cand)
    noise = noise[hit]
    if r.size == 0:
        return pd.DataFrame({c: pd.Series(dtype=float) for c in POINT_CLOUD_COLUMNS})

    range_pos = _interp_range(rd[np.clip(r[:, None] + np.arange(-1, 2), 0, n_range - 1),
                                 d[:, None]], r, n_range)
    y = _log(rd[r[:, None], (d[:, None] + np.arange(-1, 2)) % n_dop])
    d_frac = d + parabolic_offset(y[:, 0], y[:, 1], y[:, 2])
    d_signed = (d_frac + n_dop / 2) % n_dop - n_dop / 2
    t_slot = n_tx * cfg.chirp_period_s
    v_est = -d_signed / (n_dop * t_slot) * cfg.wavelength_m / 2
    v_max = cfg.max_unambiguous_velocity_mps
    if proc.tdma_disambiguation:
        # Hypotheses v_est + 2 k Vmax covering the full +/- lambda / (4 Tc) span (seed 001 eq.12).
        k = np.arange(-(n_tx // 2) - 1, n_tx // 2 + 2)
        v_hyp = v_est[:, None] + 2 * k[None, :] * v_max  # (n, H)
        span = n_tx * v_max
        valid = (v_hyp >= -span) & (v_hyp < span)
    else:
        v_hyp = v_est[:, None]
        valid = np.ones_like(v_hyp, dtype=bool)
    h_idx, h_pos, v_idx, v_pos, v_h = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    virt = virt_all[r, d].reshape(-1, 1, n_tx, cfg.n_rx)  # (n, 1, S, R)
    # Doppler phase of slot s: 2 pi f_D s Tc, f_D = -2 v / lambda (eq. 8-10): remove it.
    f_hyp = -2 * v_hyp / cfg.wavelength_m
    comp = np.exp(-2j * np.pi * f_hyp[:, :, None] * np.arange(n_tx) * cfg.chirp_period_s)
    virt_h = (virt * comp[:, :, :, None]).reshape(r.size, v_hyp.shape[1], -1)  # (n, H, 16)
    az_pow = np.abs(virt_h @ _array_dft(cfg, n_az, "horizontal")) ** 2  # (n, H, A)
    score = _tdma_hypothesis_score(cfg, virt_h, az_pow, h_idx, h_pos, v_idx, v_pos)
    best = np.argmax(np.where(valid, score, -np.inf), axis=1)
    rows = np.arange(r.size)
    velocity = v_hyp[rows, best]
    power_az = az_pow[rows, best]  # (n, A)
    a = np.argmax(power_az, axis=1)
    peak = power_az[rows, a]
    sin_term = _interp_azimuth(power_az, a)
    az, el = estimate_angles(virt_h[rows, best], sin_term, h_idx, h_pos, v_idx, v_pos, v_h)
    # Noise per virtual channel from the L-look CFAR estimate; the coherent azimuth spectrum
    # of n_h unit-weight channels has n_h times that noise power.
    sigma2 = noise / (noise_mean_factor(cf.mode, cf.n_training, cf.os_rank, looks) * looks)
    snr_db = 10 * np.log10(peak / (h_idx.size * sigma2))
    d_true = np.rint(-2 * velocity / cfg.wavelength_m * n_dop * t_slot).astype(int)
    return _point_cloud(cfg, proc, range_pos, velocity, az, el, snr_db,
                        {"range_bin": r, "doppler_bin": d_true % (n_tx * n_dop),
                         "azimuth_bin": a})


#: MIMO scheme -> chain.
MIMO_CHAINS = {"ddma": _ddma, "tdma": _tdma}


def process_frame(cfg: RadarConfig, adc: np.ndarray,
                  proc: ProcessingConfig | None = None) -> pd.DataFrame:
    """Turn one ADC frame into a point cloud.

    Parameters
    ----------
    cfg : radarsim.RadarConfig
        The radar that produced the frame (`cfg.mimo` selects the chain).
    adc : (n_chirps, n_rx, n_samples) int16, or complex64 for a complex ADC mode
        ADC samples (`RadarConfig.adc_dtype`).
    proc : ProcessingConfig, optional
        Windows, CFAR and TDMA settings; default `ProcessingConfig()`.

    Returns
    -------
    pandas.DataFrame
        One row per detection, radar frame: range_m, azimuth_deg, elevation_deg,
        radial_velocity_mps (negative = approaching), snr_db, x_m, y_m, z_m, range_bin,
        doppler_bin (0..n_chirps-1 in the full unambiguous Doppler span), azimuth_bin.

    Raises
    ------
    ValueError
        If `adc` is not an array of the config's dtype and shape, or `cfg`/`proc` are of the
        wrong type.
    """
    _check_frame(cfg, adc)
    proc = ProcessingConfig() if proc is None else proc
    if not isinstance(proc, ProcessingConfig):
        raise ValueError(f"proc must be a pipeline.ProcessingConfig, got {type(proc).__name__}")
    return MIMO_CHAINS[cfg.mimo](cfg, adc, proc)


def detection_map(cfg: RadarConfig, adc: np.ndarray,
                  proc: ProcessingConfig | None = None) -> tuple[np.ndarray, int, int]:
    """The square-law map the CFAR runs on, for tests of the detector and for plots.

    Returns
    -------
    power : ndarray
        DDMA: (n_range, n_azimuth, n_doppler) coherent Doppler-azimuth maps after empty-band
        demodulation; TDMA: (n_range, n_doppler) non-coherent sum over virtual antennas.
    looks : int
        Independent exponential looks per cell under noise (1 coherent, n_virtual for TDMA).
    cfar_axis : int
        The (cyclic) Doppler axis the CFAR runs along.
    """
    _check_frame(cfg, adc)
    proc = ProcessingConfig() if proc is None else proc
    if cfg.mimo == "ddma":
        return np.ascontiguousarray(_ddma_maps(cfg, adc, proc)["power"].transpose(1, 0, 2)), 1, 2
    return _tdma_maps(cfg, adc, proc)["power"], cfg.n_virtual, 1


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
    _check_frame(cfg, adc)
    proc = ProcessingConfig() if proc is None else proc
    if not 0 <= range_bin < cfg.n_range_bins:
        raise ValueError(f"range_bin={range_bin} outside 0..{cfg.n_range_bins - 1}")
    n_az = proc.n_azimuth_bins
    lam, tc = cfg.wavelength_m, cfg.chirp_period_s
    if cfg.mimo == "ddma":
        maps = _ddma_maps(cfg, adc, proc)
        n_dop = maps["power"].shape[2]
        power = maps["power"][:, range_bin, :].T  # (D, A)
        k = np.arange(n_dop) + n_dop * maps["tx1_band"][:, range_bin]
        k_signed = (k + cfg.n_chirps / 2) % cfg.n_chirps - cfg.n_chirps / 2
        vel = -k_signed / (cfg.n_chirps * tc) * lam / 2
    else:
        virt = _tdma_maps(cfg, adc, proc)["virt"][range_bin]  # (D, S*R)
        n_dop = virt.shape[0]
        d_signed = (np.arange(n_dop) + n_dop / 2) % n_dop - n_dop / 2
        vel = -d_signed / (n_dop * cfg.n_tx * tc) * lam / 2
        comp = np.exp(2j * np.pi * (2 * vel[:, None] / lam) * np.arange(cfg.n_tx) * tc)
        virt = (virt.reshape(n_dop, cfg.n_tx, cfg.n_rx) * comp[:, :, None]).reshape(n_dop, -1)
        power = np.abs(virt @ _array_dft(cfg, n_az, "horizontal")) ** 2
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
        "range_doppler_db": (n_range, n_doppler) power summed over virtual channels, dB, with
        Doppler in natural FFT order over the full slow-time sequence (DDMA: all chirps, before
        demodulation; TDMA: per-slot Doppler).
    """
    _check_frame(cfg, adc)
    proc = ProcessingConfig() if proc is None else proc
    # The chain's own maps: DDMA's Rx-summed energy before demodulation, TDMA's non-coherent
    # range-Doppler map over the virtual antennas (both (n_range, n_doppler)).
    if cfg.mimo == "ddma":
        p = _ddma_maps(cfg, adc, proc)["energy"]
    else:
        p = _tdma_maps(cfg, adc, proc)["power"]
    return {"range_doppler_db": 10 * np.log10(np.maximum(p, 1e-30))}
