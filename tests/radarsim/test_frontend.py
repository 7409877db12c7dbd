"""simulate_frame against analytic references (design.md sections 3, 4 and 8).

Every test synthesises a frame, runs the textbook range FFT (real, n_samples/2 bins) and
Doppler FFT in the test itself (rectangular window, targets on bin centres unless stated), and
compares with a closed-form reference named in the test: beat bin 2 S R / c, Doppler bin
-2 v / lambda, virtual-array phases d wx (+ wz), radar equation ([TI-DDMA] eq. 1) plus coherent
gains 10 log10(N/2) and 10 log10(N_chirps), k T NF B, the 6-bit shifter spur and the sigma^2/N
phase-error floor.
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import scipy.fft
import scipy.stats

import radarsim
from radarsim.config import C_MPS, K_BOLTZMANN
from radarsim.frontend import if_filter_gain

SEED = 20260123


# ----------------------------------------------------------------------------- helpers
def _db(x):
    return 10 * np.log10(x)


def range_fft(adc: np.ndarray) -> np.ndarray:
    """(C, R, N) int16 -> (C, R, N/2) complex128: rectangular-window real range FFT."""
    n = adc.shape[-1]
    return scipy.fft.rfft(adc.astype(np.float64), axis=-1)[..., : n // 2]


def range_doppler_ddma(adc: np.ndarray) -> np.ndarray:
    """(C, R, N) -> (C Doppler bins in FFT order, R, N/2) complex: Doppler FFT over all chirps."""
    return scipy.fft.fft(range_fft(adc), axis=0)


def range_doppler_tdma(cfg, adc: np.ndarray) -> np.ndarray:
    """(C, R, N) -> (n_tx slots, C / n_tx Doppler bins, R, N/2): per-slot Doppler FFT.

    Slot s holds chirps s, s + n_tx, ... fired by Tx `cfg.tx_order[s]`."""
    x = range_fft(adc)
    x = x.reshape(cfg.n_chirps // cfg.n_tx, cfg.n_tx, *x.shape[1:]).swapaxes(0, 1)
    return scipy.fft.fft(x, axis=1)


def scene(make_scene, cfg, range_m, az_deg=0.0, el_deg=0.0, v_mps=0.0, *, amp_lsb=None,
          rcs_m2=10.0):
    """One scatterer; with `amp_lsb` the RCS is chosen so one Tx-Rx tone has that peak (LSB)."""
    sc = make_scene([(range_m, az_deg, el_deg, v_mps, 1.0)])
    if amp_lsb is not None:
        p1 = radarsim.received_power_w(cfg, sc)[0]
        rcs_m2 = (amp_lsb / cfg.adc_code_per_sqrt_w) ** 2 / 2 / p1
    return make_scene([(range_m, az_deg, el_deg, v_mps, rcs_m2)])


def beat_bin(cfg, range_m: float) -> float:
    """Analytic beat-frequency bin: f_b = 2 S R / c over the bin width adc_rate / n_samples."""
    return 2 * cfg.slope_hz_per_s * range_m / C_MPS / (cfg.adc_rate_sps / cfg.n_samples)


def doppler_bin(cfg, v_mps: float, n_chirps: int, period_s: float) -> float:
    """Analytic slow-time bin (signed): f_D = -2 v / lambda (design.md 3) over 1 / (N T)."""
    return -2 * v_mps / cfg.wavelength_m * n_chirps * period_s


def on_bin_range(cfg, b: int) -> float:
    return b * cfg.range_resolution_m


def on_bin_velocity(cfg, k: int) -> float:
    """Radial velocity whose Tx1 Doppler lands exactly on signed bin k (DDMA and TDMA)."""
    return -k * cfg.velocity_resolution_mps


def radar_equation_snr(cfg, range_m: float, rcs_m2: float) -> float:
    """Per-sample SNR at boresight from [TI-DDMA] eq. 1 / Richards ch. 2, computed here from the
    config fields: Pt Gt Gr lambda^2 sigma / ((4 pi)^3 R^4 L) / (k T NF B), B = adc_rate / 2."""
    pt = 1e-3 * 10 ** (cfg.tx_power_dbm / 10)
    g = 10 ** ((cfg.tx_antenna_gain_dbi + cfg.rx_antenna_gain_dbi) / 10)
    loss = 10 ** (cfg.system_loss_db / 10)
    pr = pt * g * cfg.wavelength_m ** 2 * rcs_m2 / ((4 * np.pi) ** 3 * range_m ** 4 * loss)
    pn = K_BOLTZMANN * cfg.temperature_k * 10 ** (cfg.noise_figure_db / 10) * cfg.adc_rate_sps / 2
    return pr / pn


def virtual_vector(cfg, rd, rbin: int, k0: int = 0) -> np.ndarray:
    """(n_tx x n_rx,) complex peaks in the demodulated order Tx1, Tx3, Tx4, Tx2 x Rx1..Rx4.

    DDMA: Tx in sub-band p sits at Doppler bin k0 + p N/n_subbands; TDMA: slot p, bin k0."""
    if cfg.mimo == "ddma":
        step = cfg.n_chirps // cfg.n_subbands
        return np.concatenate([rd[(k0 + p * step) % cfg.n_chirps, :, rbin]
                               for p in range(cfg.n_tx)])
    return np.concatenate([rd[p, k0 % rd.shape[1], :, rbin] for p in range(cfg.n_tx)])


# ----------------------------------------------------------------------------- range
@pytest.mark.parametrize("range_m", [7 * 1.3183, 57 * 1.3183, 150 * 1.3183, 100.3, 231.7],
                         ids=["bin7", "bin57", "bin150", "100.3m", "231.7m"])
def test_beat_tone_lands_in_range_bin_2SR_over_c(make_config, make_scene, range_m):
    """design.md 3: beat frequency 2 S R / c -> range bin 2 S R / c x n_samples / adc_rate."""
    cfg = make_config()
    adc = radarsim.simulate_frame(cfg, scene(make_scene, cfg, range_m, amp_lsb=200.0),
                                  np.random.default_rng(SEED))
    profile = np.sum(np.abs(range_fft(adc)) ** 2, axis=(0, 1))
    expected = beat_bin(cfg, range_m)
    assert expected == pytest.approx(range_m / cfg.range_resolution_m)
    assert int(np.argmax(profile)) == round(expected)
    if abs(expected - round(expected)) < 1e-3:
        # On a bin centre a rectangular window puts (nearly) all the tone in one bin.
        assert profile[round(expected)] / profile.sum() > 0.99


# ----------------------------------------------------------------------------- Doppler
# Signed Doppler bins of Tx1 (bin 0.1065 m/s): +-47 -> -+5.0 m/s; +-282 -> -+30.0 m/s; 380.
@pytest.mark.parametrize("k_signed", [47, -47, 282, -282, 380, -380],
                         ids=["approach5", "recede5", "approach30", "recede30", "approach40",
                              "recede40"])
def test_ddma_subbands_tx1_tx3_tx4_tx2_then_two_empty(make_config, make_scene, k_signed):
    """[TI-DDMA] figures 4-5 / design.md 4.3: Tx k's echo shifts by its sub-band index; the order
    is Tx1, Tx3, Tx4, Tx2 then two empty sub-bands; receding targets have negative Doppler.

    Each Tx is tagged with a static gain (Tx1 0, Tx3 -2, Tx4 -4, Tx2 -6 dB) so its sub-band
    can be identified from the energy alone."""
    tags = {1: 0.0, 3: -2.0, 4: -4.0, 2: -6.0}
    cfg = make_config(tx_gain_error_db=tuple(tags[t] for t in range(1, 5)))
    v = on_bin_velocity(cfg, k_signed)
    r = on_bin_range(cfg, 40)
    adc = radarsim.simulate_frame(cfg, scene(make_scene, cfg, r, v_mps=v, amp_lsb=300.0),
                                  np.random.default_rng(SEED))
    spec = np.sum(np.abs(range_doppler_ddma(adc)[:, :, 40]) ** 2, axis=1)  # (768,)
    n, nb = cfg.n_chirps, cfg.n_chirps // cfg.n_subbands
    k0 = round(doppler_bin(cfg, v, n, cfg.chirp_period_s))
    assert k0 == k_signed
    assert np.sign(k0) == -np.sign(v)  # receding (v > 0) -> negative Doppler frequency
    # Tx1's peak sits at the signed bin k0 and gives back the velocity: v = -f_D lambda / 2.
    assert int(np.argmax(spec)) == k0 % n
    f_d = k0 / (n * cfg.chirp_period_s)
    assert -f_d * cfg.wavelength_m / 2 == pytest.approx(v)
    # Energy per sub-band, each 128-bin block centred on where Tx p would land.
    idx = (k0 + nb * np.arange(cfg.n_subbands)[:, None] + np.arange(-nb // 2, nb // 2)) % n
    energy = spec[idx].sum(axis=1)
    rel_db = _db(energy / energy[0])
    # Occupied sub-bands p = 0..3 carry Tx1, Tx3, Tx4, Tx2: 0, -2, -4, -6 dB (the floor
    # quantisation spur of Tx3, -34.5 - 2 dB, adds coherently to Tx2's band: < 0.3 dB).
    np.testing.assert_allclose(rel_db[:4], [0.0, -2.0, -4.0, -6.0], atol=0.35)
    # Two empty sub-bands: only the -34.5 dBc shifter spurs and noise.
    assert np.all(rel_db[4:] < -30.0)


@pytest.mark.parametrize("k_signed", [47, -47], ids=["approach5", "recede5"])
def test_tdma_doppler_sign_and_bin(make_config, make_scene, k_signed):
    """TDMA: each Tx's 192 chirps at 4 Tc; the Doppler bin is -2 v / lambda x 192 x 4 Tc,
    negative for a receding target [TI-VEXT]."""
    cfg = make_config("tdma")
    v = on_bin_velocity(cfg, k_signed)
    adc = radarsim.simulate_frame(cfg, scene(make_scene, cfg, on_bin_range(cfg, 40), v_mps=v,
                                             amp_lsb=300.0), np.random.default_rng(SEED))
    rd = range_doppler_tdma(cfg, adc)  # (4, 192, 4, 192)
    n_slow = cfg.n_chirps // cfg.n_tx
    k0 = round(doppler_bin(cfg, v, n_slow, cfg.n_tx * cfg.chirp_period_s))
    assert k0 == k_signed
    for slot in range(cfg.n_tx):
        spec = np.sum(np.abs(rd[slot, :, :, 40]) ** 2, axis=1)
        assert int(np.argmax(spec)) == k0 % n_slow


# ----------------------------------------------------------------------------- virtual array
ERRORS = {
    "ideal": dict(),
    "static_errors": dict(tx_phase_error_deg=(0.0, 25.0, -12.0, 7.0),
                          tx_gain_error_db=(0.0, -1.5, 2.0, 0.7)),
}


@pytest.mark.parametrize("errors", list(ERRORS.values()), ids=list(ERRORS))
@pytest.mark.parametrize("az_deg, el_deg", [(20.0, 10.0), (-35.0, -5.0)])
@pytest.mark.parametrize("mimo", ["ddma", "tdma"])
def test_virtual_array_phases_match_geometry(make_config, make_scene, mimo, az_deg, el_deg,
                                             errors):
    """design.md 3 / [TI-DDMA] fig. 20, eqs. 18-21: virtual element d = 0..11 carries d wx, Tx2's
    four elements (2..5) carry d wx + wz, wx = pi sin(az) cos(el), wz = 1.6 pi sin(el); static
    per-Tx phase and gain errors add to every element of that Tx."""
    cfg = make_config(mimo, phase_quantization="none", **errors)
    rbin = 30
    adc = radarsim.simulate_frame(cfg, scene(make_scene, cfg, on_bin_range(cfg, rbin), az_deg,
                                             el_deg, amp_lsb=300.0), np.random.default_rng(SEED))
    rd = range_doppler_ddma(adc) if mimo == "ddma" else range_doppler_tdma(cfg, adc)
    x = virtual_vector(cfg, rd, rbin)  # (16,) Tx1, Tx3, Tx4, Tx2 x Rx1..4
    az, el = np.radians(az_deg), np.radians(el_deg)
    wx, wz = np.pi * np.sin(az) * np.cos(el), 1.6 * np.pi * np.sin(el)
    d = np.r_[np.arange(12), np.arange(2, 6)]
    expected = d * wx + np.r_[np.zeros(12), np.full(4, wz)]
    tx_of = np.repeat(cfg.tx_order, cfg.n_rx)  # 1-based Tx of each virtual element
    expected = expected + np.radians(np.asarray(cfg.tx_phase_error_deg))[tx_of - 1]
    resid = np.angle(x * np.conj(x[0]) * np.exp(-1j * (expected - expected[0])))
    np.testing.assert_allclose(resid, 0.0, atol=0.02)  # SNR ~ 70 dB: phase noise < 1e-3 rad
    gain_db = 20 * np.log10(np.abs(x) / np.abs(x[0]))
    np.testing.assert_allclose(gain_db, np.asarray(cfg.tx_gain_error_db)[tx_of - 1], atol=0.05)


def test_tdma_slot_schedule_each_tx_only_in_its_slots(make_config, make_scene):
    """TDMA: chirp c fires only Tx tx_order[c mod 4]. With gains tagged per Tx (Tx1 0, Tx3 -6,
    Tx4 -12, Tx2 -18 dB) the per-chirp echo amplitude follows the slot exactly; any other Tx
    leaking into a slot would change it."""
    tags = {1: 0.0, 3: -6.0, 4: -12.0, 2: -18.0}
    cfg = make_config("tdma", tx_gain_error_db=tuple(tags[t] for t in range(1, 5)))
    w = radarsim.transmit_phasors(cfg)
    slot_tx = np.array(cfg.tx_order)[np.arange(cfg.n_chirps) % cfg.n_tx]
    np.testing.assert_array_equal(np.abs(w) > 0, slot_tx[None, :] == np.arange(1, 5)[:, None])
    adc = radarsim.simulate_frame(cfg, scene(make_scene, cfg, on_bin_range(cfg, 25), 15.0,
                                             amp_lsb=2000.0), np.random.default_rng(SEED))
    peak = np.abs(range_fft(adc)[:, 0, 25])  # (768,) Rx1
    rel_db = 20 * np.log10(peak / peak[0])
    np.testing.assert_allclose(rel_db, [tags[t] for t in slot_tx], atol=0.1)


def test_ddma_transmit_phasors_all_tx_every_chirp(make_config):
    cfg = make_config(phase_quantization="none")
    w = radarsim.transmit_phasors(cfg)
    assert w.shape == (4, 768)
    np.testing.assert_allclose(np.abs(w), 1.0)
    step = np.angle(w[:, 1:] * np.conj(w[:, :-1]), deg=True)
    np.testing.assert_allclose(step[[0, 2, 3]], [[0.0] * 767, [60.0] * 767, [120.0] * 767],
                               atol=1e-9)


# ----------------------------------------------------------------------------- SNR and noise
@pytest.mark.parametrize("mimo, doppler_gain_db", [("ddma", 28.85), ("tdma", 22.83)],
                         ids=["ddma", "tdma"])
def test_peak_snr_matches_radar_equation_plus_coherent_gains(make_config, make_scene, mimo,
                                                             doppler_gain_db):
    """[TI-DDMA] eq. 1 (radar equation) + design.md 8 coherent gains: real range FFT of 384 samples
    10 log10(192) = 22.83 dB, Doppler FFT 10 log10(768) = 28.85 dB (DDMA) or 10 log10(192) =
    22.83 dB (TDMA, one Tx's chirps). Rectangular windows, target on a range and Doppler bin
    centre, noise floor from target-free range bins of the same spectrum."""
    cfg = make_config(mimo)
    rbin, rcs = 24, 10.0
    r = on_bin_range(cfg, rbin)
    sc = scene(make_scene, cfg, r, rcs_m2=rcs)
    snr_sample = radar_equation_snr(cfg, r, rcs)
    assert if_filter_gain(np.array([2 * cfg.slope_hz_per_s * r / C_MPS]))[0] == \
        pytest.approx(1.0, abs=1e-9)
    assert radarsim.expected_sample_snr_db(cfg, sc)[0] == pytest.approx(_db(snr_sample), abs=1e-9)
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(SEED))
    if mimo == "ddma":
        rd = range_doppler_ddma(adc)          # Tx1 at Doppler bin 0
        peak = np.abs(rd[0, :, rbin]) ** 2
        noise = np.mean(np.abs(rd[:, :, 100:190]) ** 2)
    else:
        rd = range_doppler_tdma(cfg, adc)[0]  # slot 0 = Tx1
        peak = np.abs(rd[0, :, rbin]) ** 2
        noise = np.mean(np.abs(rd[:, :, 100:190]) ** 2)
    measured_db = _db(np.mean(peak) / noise)
    expected_db = _db(snr_sample) + 22.83 + doppler_gain_db
    assert expected_db == pytest.approx(_db(snr_sample) + _db(192) + _db(
        cfg.n_chirps if mimo == "ddma" else cfg.n_chirps // 4), abs=0.01)
    # Peak SNR ~ 41 dB (DDMA): the noise moves the peak by ~0.1 dB rms, so 0.5 dB is ~5 sigma.
    assert measured_db == pytest.approx(expected_db, abs=0.5)


def test_ddma_signal_energy_gain_over_tdma_is_6_db(make_config, make_scene):
    """design.md 8: same frame time, Nt = 4 -> DDMA collects 10 log10 4 = 6.02 dB more signal
    energy per Tx-Rx channel than TDMA (peak power after range and Doppler FFT, equal noise)."""
    peaks = {}
    for mimo in ("ddma", "tdma"):
        cfg = make_config(mimo)
        adc = radarsim.simulate_frame(cfg, scene(make_scene, cfg, on_bin_range(cfg, 24),
                                                 amp_lsb=20.0), np.random.default_rng(SEED))
        rd = range_doppler_ddma(adc) if mimo == "ddma" else range_doppler_tdma(cfg, adc)[0]
        peaks[mimo] = np.mean(np.abs(rd[0, :, 24]) ** 2) / np.mean(np.abs(rd[:, :, 100:190]) ** 2)
    assert _db(peaks["ddma"] / peaks["tdma"]) == pytest.approx(6.02, abs=0.3)


def test_pure_noise_frame_is_gaussian_with_k_t_nf_b_power(make_config):
    """K = 0: the frame is zero-mean white Gaussian noise of power k T NF B (B = adc_rate / 2)
    at the ADC input, i.e. variance noise_rms_lsb^2 (+ 1/12 LSB^2 of rounding)."""
    cfg = make_config()
    adc = radarsim.simulate_frame(cfg, radarsim.Scatterers.empty(), np.random.default_rng(SEED))
    assert adc.shape == (768, 4, 384) and adc.dtype == np.int16
    x = adc.astype(np.float64).ravel()
    ktfb = K_BOLTZMANN * cfg.temperature_k * 10 ** (cfg.noise_figure_db / 10) * 15e6
    power_w = (x.var() - 1 / 12) / cfg.adc_code_per_sqrt_w ** 2
    assert _db(power_w / ktfb) == pytest.approx(0.0, abs=0.5)
    assert _db(power_w / ktfb) == pytest.approx(0.0, abs=0.02)  # n = 1.2e6: se 0.006 dB
    # Gaussian: mean, skewness and excess kurtosis within ~4 standard errors of 0.
    n = x.size
    assert abs(x.mean()) < 4 * x.std() / math.sqrt(n)
    assert abs(scipy.stats.skew(x)) < 4 * math.sqrt(6 / n)
    assert abs(scipy.stats.kurtosis(x)) < 4 * math.sqrt(24 / n)
    # Distribution: a Gaussian of std noise_rms_lsb rounded to integers, P(k) = Phi((k + 1/2)
    # / s) - Phi((k - 1/2) / s); chi-square goodness of fit over |k| <= 4 s (tails merged).
    s = cfg.noise_rms_lsb
    edges = np.arange(-math.ceil(4 * s), math.ceil(4 * s) + 1)
    inner = np.array([np.count_nonzero(adc == k) for k in edges])
    observed = np.r_[np.count_nonzero(adc < edges[0]), inner, np.count_nonzero(adc > edges[-1])]
    cdf = scipy.stats.norm.cdf(np.r_[edges - 0.5, edges[-1] + 0.5] / s)
    p_bins = np.r_[cdf[0], np.diff(cdf), 1 - cdf[-1]]
    assert scipy.stats.chisquare(observed, n * p_bins).pvalue > 1e-3
    # White: the range-FFT noise power is flat across bins (each bin averages 3072 spectra).
    per_bin = np.mean(np.abs(range_fft(adc)) ** 2, axis=(0, 1))[1:]
    assert np.ptp(_db(per_bin)) < 0.5
    assert _db(per_bin.mean() / (cfg.n_samples * x.var())) == pytest.approx(0.0, abs=0.05)


def test_same_seed_same_bits(make_config, make_scene):
    cfg = make_config(phase_noise_deg_rms=2.0)  # both random sources in use
    sc = scene(make_scene, cfg, 50.0, 10.0, 0.0, -12.0)
    a = radarsim.simulate_frame(cfg, sc, np.random.default_rng(7))
    b = radarsim.simulate_frame(cfg, sc, np.random.default_rng(7))
    c = radarsim.simulate_frame(cfg, sc, np.random.default_rng(8))
    assert a.dtype == np.int16 and a.shape == (768, 4, 384)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)


def test_close_strong_target_saturates_and_warns(make_config, make_scene):
    """A 1000 m^2 reflector at 0.5 m: -10 dBm per Tx-Rx pair ([TI-DDMA] eq. 1), 10 dB above the
    -20 dBm full scale (about 3 x 32767 LSB peak per Tx) -> clipped, reported by a warning."""
    cfg = make_config()
    sc = make_scene([(0.5, 0.0, 0.0, 0.0, 1000.0)])
    with pytest.warns(radarsim.ADCSaturationWarning, match="clipped"):
        adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(SEED))
    assert adc.max() == 32767 and adc.min() == -32768
    assert radarsim.saturation_fraction(adc) > 0
    # A normal scene is not reported.
    with warnings.catch_warnings():
        warnings.simplefilter("error", radarsim.ADCSaturationWarning)
        adc = radarsim.simulate_frame(cfg, make_scene([(30.0, 0.0, 0.0, 0.0, 10.0)]),
                                      np.random.default_rng(SEED))
    assert radarsim.saturation_fraction(adc) == 0


def test_bad_arguments_raise(make_config):
    cfg = make_config()
    with pytest.raises(ValueError, match="rng must be a numpy.random.Generator"):
        radarsim.simulate_frame(cfg, radarsim.Scatterers.empty(), 0)
    with pytest.raises(ValueError, match="scatterers must be a radarsim.Scatterers"):
        radarsim.simulate_frame(cfg, np.zeros((1, 3)), np.random.default_rng(0))
    with pytest.raises(ValueError, match="cfg must be a RadarConfig"):
        radarsim.simulate_frame({}, radarsim.Scatterers.empty(), np.random.default_rng(0))
    with pytest.raises(ValueError, match="rng is required"):
        radarsim.transmit_phasors(make_config(phase_noise_deg_rms=1.0))


def test_scatterer_behind_radar_is_silent(make_config):
    """Cosine pattern: zero gain behind the radar, so the frame is pure noise."""
    cfg = make_config()
    behind = radarsim.Scatterers([[-20.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]], [1e4])
    a = radarsim.simulate_frame(cfg, behind, np.random.default_rng(1))
    b = radarsim.simulate_frame(cfg, radarsim.Scatterers.empty(), np.random.default_rng(1))
    np.testing.assert_array_equal(a, b)
    # Mixed set: the scatterer behind is dropped, the one in front is synthesised unchanged.
    front = radarsim.Scatterers([[30.0, 5.0, 0.0]], [[-3.0, 0.0, 0.0]], [10.0])
    mixed = radarsim.Scatterers.concatenate([behind, front])
    np.testing.assert_array_equal(radarsim.simulate_frame(cfg, mixed, np.random.default_rng(2)),
                                  radarsim.simulate_frame(cfg, front, np.random.default_rng(2)))


# ----------------------------------------------------------------------------- shifter errors
def _period3_spur_dbc(err_deg) -> dict[int, float]:
    """Spurs of a 6-chirp code whose phase error e_c (deg) has period 3: Fourier coefficients of
    exp(j e_c) at +2 and +4 sub-bands over the one at 0 (the wanted line), dBc, keyed by offset."""
    e = np.exp(1j * np.radians(np.asarray(err_deg, dtype=float)))
    c = np.arange(6)
    x = {q: np.mean(e * np.exp(-2j * np.pi * q * c / 6)) for q in (0, 1, 2, 3, 4, 5)}
    # A period-3 error has no odd lines.
    assert max(abs(x[q]) for q in (1, 3, 5)) < 1e-12
    return {q: 20 * np.log10(abs(x[q]) / abs(x[0])) for q in (2, 4)}


def test_period3_spur_analytic_value():
    """Derivation of the design.md 8 figure. Floor rule (table 4): Tx3 programs 300, 240, 180, 120,
    60 deg as 298.125, 236.25, 180, 118.125, 56.25, so its applied phase errs by
    e = (0, 1.875, 3.75) deg repeating with period 3 (Tx4: 0, 3.75, 1.875). A period-3 error
    puts lines at +-2 sub-bands; to first order each is the DFT of e - mean over 3 chirps,
    delta / sqrt(3) with delta = 1.875 deg = pi/96 rad: 20 log10(pi / (96 sqrt 3)) = -34.47 dBc.
    Second-order terms split the two lines by 0.16 dB: for both rules the lines falling in the
    empty sub-bands 4 and 5 are -34.55 dBc, the others (in Tx2's and Tx1's sub-bands 3 and 0)
    -34.39 dBc. The round rule (errors 0, 1.875, -1.875) has the same first-order
    spur. Tx1 (0 deg) and Tx2 (180 deg = 32 codes) are exact: no spur."""
    small_angle = 20 * np.log10(np.pi / 96 / math.sqrt(3))
    assert small_angle == pytest.approx(-34.47, abs=0.01)
    floor_tx3 = [0, 1.875, 3.75, 0, 1.875, 3.75]
    floor_tx4 = [0, 3.75, 1.875, 0, 3.75, 1.875]
    round_tx3 = [0, 1.875, -1.875, 0, 1.875, -1.875]
    for err in (floor_tx3, floor_tx4, round_tx3):
        np.testing.assert_allclose(list(_period3_spur_dbc(err).values()), small_angle, atol=0.1)


@pytest.mark.parametrize("rule", ["floor", "round"])
def test_6bit_shifter_spur_in_empty_subbands(make_config, make_scene, rule):
    """design.md 8: with the 6-bit shifter, Tx4 (120 deg steps) leaks a -34.47 dBc spur into
    sub-band 4 and Tx3 (60 deg steps) into sub-band 5 (the two empty ones), each relative to one
    Tx's line; Tx1 and Tx2 (0 and 180 deg steps) leak nothing. Strong target (~90 dB peak SNR),
    on range and Doppler bin centres."""
    cfg = make_config(phase_quantization=rule)
    codes = cfg.phase_codes() * cfg.phase_lsb_deg
    err = cfg.programmed_phase_deg() - codes  # applied = -codes = ideal + err
    # Tx3 sits in sub-band 1: its +4 line lands in sub-band 5; Tx4 (sub-band 2): +2 -> 4.
    expected = {3: _period3_spur_dbc(err[2])[4], 4: _period3_spur_dbc(err[3])[2]}
    np.testing.assert_allclose(list(expected.values()), -34.55, atol=0.01)
    rbin, k = 40, 30
    sc = scene(make_scene, cfg, on_bin_range(cfg, rbin), v_mps=on_bin_velocity(cfg, k),
               amp_lsb=1000.0)
    spec = np.abs(range_doppler_ddma(radarsim.simulate_frame(
        cfg, sc, np.random.default_rng(SEED)))[:, :, rbin]) ** 2  # (768, 4)
    # dBc against the leaking Tx's own line: Tx3 in sub-band 1, Tx4 in 2 (no spur lands there;
    # Tx1's line is not used because Tx4's other spur falls on it and beats with it).
    line3, line4 = spec[k + 1 * 128], spec[k + 2 * 128]
    sub4, sub5 = spec[k + 4 * 128], spec[k + 5 * 128]
    np.testing.assert_allclose(_db(sub4 / line4), expected[4], atol=0.05)
    np.testing.assert_allclose(_db(sub5 / line3), expected[3], atol=0.05)
    # Only Tx1 and Tx2 on (Tx3 and Tx4 at -300 dB): the empty sub-bands hold thermal noise only.
    cfg12 = cfg.replace(tx_gain_error_db=(0.0, 0.0, -300.0, -300.0))
    spec12 = np.abs(range_doppler_ddma(radarsim.simulate_frame(
        cfg12, sc, np.random.default_rng(SEED)))[:, :, rbin]) ** 2
    empty = spec12[(k + 128 * np.arange(1, 6)[[0, 1, 3, 4]]) % 768]
    assert np.all(_db(empty / spec12[k]) < -70)


def test_ideal_shifter_has_no_spur(make_config, make_scene):
    cfg = make_config(phase_quantization="none")
    sc = scene(make_scene, cfg, on_bin_range(cfg, 40), amp_lsb=1000.0)
    spec = np.abs(range_doppler_ddma(radarsim.simulate_frame(
        cfg, sc, np.random.default_rng(SEED)))[:, :, 40]) ** 2
    assert np.all(_db(spec[[512, 640]] / spec[0]) < -70)


@pytest.mark.parametrize("sigma_deg, reference_dbc", [(2.0, -58.0), (5.0, -50.0)])
def test_random_phase_error_floor_sigma2_over_n(make_config, make_scene, sigma_deg,
                                                reference_dbc):
    """design.md 8: a random per-chirp phase error of sigma rad leaves a white floor of
    (e^{sigma^2} - 1) / N ~ sigma^2 / N below the line (-58 dBc at 2 deg, -50 dBc at 5 deg for
    N = 768). Measured with one Tx (its empty sub-band: 384 bins x 4 Rx), ideal shifter, a
    strong target (thermal floor ~ -92 dBc); and with four Tx, whose independent errors add:
    4 sigma^2 / N in the two empty sub-bands."""
    s2 = np.radians(sigma_deg) ** 2
    n = 768
    exact = _db((np.exp(s2) - 1) / n)
    assert exact == pytest.approx(reference_dbc, abs=0.1)
    rbin = 40
    for n_tx, floor_db, empty in ((1, exact, np.arange(384 + 32, 768 - 32)),
                                  (4, exact + _db(4), np.arange(4 * 128 + 16, 768 - 16))):
        cfg = make_config(n_tx=n_tx, phase_quantization="none", phase_noise_deg_rms=sigma_deg)
        sc = scene(make_scene, cfg, on_bin_range(cfg, rbin), amp_lsb=1000.0)
        spec = np.abs(range_doppler_ddma(radarsim.simulate_frame(
            cfg, sc, np.random.default_rng(SEED)))[:, :, rbin]) ** 2
        measured = _db(np.mean(spec[empty]) / np.mean(spec[0]))
        # ~300 independent bins per estimate: +-0.25 dB rms; 1 dB is ~4 sigma.
        assert measured == pytest.approx(floor_db, abs=1.0), n_tx


# ----------------------------------------------------------------------------- radar budget
def albersheim_snr_db(pd: float, pfa: float) -> float:
    """Albersheim's single-pulse SNR for a steady target (Richards eq. 6.34)."""
    a = math.log(0.62 / pfa)
    b = math.log(pd / (1 - pd))
    return 10 * math.log10(a + 0.12 * a * b + 1.7 * b)


def test_10m2_car_at_200m_is_detectable_with_ddma(make_config, make_scene):
    """design.md 4.1: the defaults make a 10 m^2 car detectable near the published 200 m.
    Per-sample SNR ([TI-DDMA] eq. 1, default budget) -44.0 dB; coherent gains 22.83 (range) +
    28.85 (Doppler) + 10.79 (12-element azimuth) = 62.47 dB; Hann losses 2 x 1.76 dB ->
    detection SNR 14.9 dB, above Albersheim's 13.1 dB for Pd = 0.9, Pfa = 1e-6."""
    cfg = make_config()
    car = make_scene([(200.0, 0.0, 0.0, 0.0, 10.0)])
    snr_sample_db = radarsim.expected_sample_snr_db(cfg, car)[0]
    assert snr_sample_db == pytest.approx(-44.0, abs=0.1)
    detection_db = snr_sample_db + 22.83 + 28.85 + 10.79 - 2 * 1.76
    assert detection_db == pytest.approx(14.95, abs=0.1)
    assert albersheim_snr_db(0.9, 1e-6) == pytest.approx(13.1, abs=0.05)
    assert detection_db > albersheim_snr_db(0.9, 1e-6)
    # Simulated: car on a range-bin centre near 200 m, approaching at 20 m/s on a Doppler bin;
    # coherent sum of the 12 horizontal virtual channels at boresight (rectangular windows, so
    # no Hann loss: expect 14.95 + 3.52 = 18.5 dB, +-1 dB rms from the noise on the peak).
    rbin, k = 152, 188
    v = on_bin_velocity(cfg, k)
    car = make_scene([(on_bin_range(cfg, rbin), 0.0, 0.0, v, 10.0)])
    rd = range_doppler_ddma(radarsim.simulate_frame(cfg, car, np.random.default_rng(SEED)))
    horiz = rd[(k + 128 * np.arange(3)) % 768]            # (3 Tx, 4 Rx, 192)
    peak = np.abs(horiz[:, :, rbin].sum()) ** 2
    noise = 12 * np.mean(np.abs(rd[:, :, 10:100]) ** 2)
    measured = _db(peak / noise)
    expected = radar_equation_snr(cfg, on_bin_range(cfg, rbin), 10.0)
    expected_db = _db(expected) + _db(192 * 768 * 12) + _db(if_filter_gain(
        np.array([2 * cfg.slope_hz_per_s * on_bin_range(cfg, rbin) / C_MPS]))[0])
    assert measured == pytest.approx(expected_db, abs=3.0)
    assert measured > albersheim_snr_db(0.9, 1e-6)
