"""ADC frame -> point cloud, DDMA chain and TDMA baseline, against analytic references.

Targets are synthesised at a chosen *expected detection SNR*: the per-sample SNR of the radar
equation plus the coherent gains of design.md 8 (range 10 log10(N/2), Doppler 10 log10(chirps per
Tx), azimuth 10 log10(12)) minus the two Hann window losses (2 x 1.76 dB, Harris 1978).
"""
import numpy as np
import pandas as pd
import pytest

import pipeline
import radarsim
from pipeline.cfar import cfar_map
from pipeline.kernels import doppler_fft, range_fft, window

HANN_LOSS_DB = 1.76
SCHEMES = {  # id -> (preset, ProcessingConfig overrides, |v| limit m/s)
    "ddma": ("ddma", {}, 40.0),
    "tdma": ("tdma", {}, 40.0),
    "tdma_raw": ("tdma", {"tdma_disambiguation": False}, 10.0),
}
#: Every registered scheme (tests parametrised over the registry).
REGISTRY = sorted(radarsim.MIMO_SCHEMES)


def coherent_gain_db(cfg):
    # Chirps whose energy each Tx contributes, from the scheme's transmit code: DDMA and BPM
    # every chirp, TDMA one chirp in n_tx.
    chirps_per_tx = float(np.sum(cfg.scheme.transmit_code(cfg).gain[0] ** 2))
    return (10 * np.log10(cfg.n_samples / 2) + 10 * np.log10(chirps_per_tx)
            + 10 * np.log10(12) - 2 * HANN_LOSS_DB)


def scene_at_snr(cfg, make_scene, targets):
    """targets: rows (range_m, az_deg, el_deg, v_mps, detection_snr_db) -> Scatterers."""
    t = np.atleast_2d(np.asarray(targets, float))
    unit = make_scene(np.column_stack([t[:, :4], np.ones(len(t))]))
    s1 = radarsim.expected_sample_snr_db(cfg, unit)
    rcs = 10 ** ((t[:, 4] - s1 - coherent_gain_db(cfg)) / 10)
    return make_scene(np.column_stack([t[:, :4], rcs]))


def best_near(pc, range_m, gate_m=2.0):
    near = pc[(pc.range_m - range_m).abs() < gate_m]
    return None if near.empty else near.loc[near.snr_db.idxmax()]


@pytest.mark.parametrize("scheme", list(SCHEMES), ids=list(SCHEMES))
def test_point_targets_accuracy(scheme, make_config, make_scene):
    """Range <= 0.66 m (half a cell), velocity <= 0.11 m/s (about one bin, never
    aliased), azimuth <= 1.5 deg, elevation <= 3 deg for SNR >= 20 dB targets over range
    3-240 m, azimuth +/-60 deg, elevation +/-15 deg."""
    preset, overrides, v_lim = SCHEMES[scheme]
    cfg = make_config(preset, antenna_pattern="isotropic")
    proc = pipeline.ProcessingConfig().replace(**overrides)
    rng = np.random.default_rng({"ddma": 11, "tdma": 12, "tdma_raw": 13}[scheme])
    n = 24
    targets = np.column_stack([rng.uniform(3, 240, n), rng.uniform(-60, 60, n),
                               rng.uniform(-15, 15, n), rng.uniform(-v_lim, v_lim, n),
                               rng.uniform(23, 32, n)])
    errors = []
    for r, az, el, v, snr in targets:
        adc = radarsim.simulate_frame(cfg, scene_at_snr(cfg, make_scene, [r, az, el, v, snr]),
                                      rng)
        best = best_near(pipeline.process_frame(cfg, adc, proc), r)
        assert best is not None, f"missed target at r={r:.1f} az={az:.1f} v={v:.1f}"
        errors.append([best.range_m - r, best.radial_velocity_mps - v,
                       best.azimuth_deg - az, best.elevation_deg - el])
    err = np.abs(np.array(errors))
    assert err[:, 0].max() <= 0.66
    assert err[:, 1].max() <= 0.11
    assert err[:, 2].max() <= 1.5
    assert err[:, 3].max() <= 3.0


def test_tdma_without_disambiguation_aliases(make_config, make_scene):
    """Beyond +/-Vmax = lambda / (16 Tc) = 10.22 m/s the raw TDMA velocity wraps by 2 Vmax;
    hypothesis testing ([TI-VEXT] sec. 4) recovers it, DDMA never aliases."""
    rng = np.random.default_rng(3)
    v_true = 25.0
    for preset, disamb, expect in [("tdma", False, None), ("tdma", True, v_true),
                                   ("ddma", True, v_true)]:
        cfg = make_config(preset, antenna_pattern="isotropic")
        vmax = cfg.max_unambiguous_velocity_mps
        expect = v_true - 2 * vmax if expect is None else expect
        adc = radarsim.simulate_frame(cfg, scene_at_snr(cfg, make_scene,
                                                        [60, 10, 0, v_true, 28]), rng)
        proc = pipeline.ProcessingConfig().replace(tdma_disambiguation=disamb)
        best = best_near(pipeline.process_frame(cfg, adc, proc), 60)
        assert best.radial_velocity_mps == pytest.approx(expect, abs=0.11)


@pytest.mark.parametrize("v", [-39.0, -20.0, -7.0, 7.0, 20.0, 39.0])
def test_ddma_unwraps_both_signs_over_full_span(v, make_config, make_scene):
    """Empty-band demodulation unwraps over +/-lambda/(4 Tc) for both signs, including positive
    velocities above one sub-band (the cyclic-index bug in one TI implementation)."""
    cfg = make_config("ddma", antenna_pattern="isotropic")
    rng = np.random.default_rng(int(abs(v) * 10))
    adc = radarsim.simulate_frame(cfg, scene_at_snr(cfg, make_scene, [80, -20, 0, v, 25]), rng)
    best = best_near(pipeline.process_frame(cfg, adc), 80)
    assert best.radial_velocity_mps == pytest.approx(v, abs=0.11)


def test_two_targets_same_range_bin_found(make_config, make_scene):
    cfg = make_config("ddma", antenna_pattern="isotropic")
    r = 70 * cfg.range_resolution_m
    sc = scene_at_snr(cfg, make_scene, [[r, -25, 0, -8.0, 27], [r + 0.2, 30, 0, 12.0, 27]])
    pc = pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, sc, np.random.default_rng(4)))
    for az, v in [(-25, -8.0), (30, 12.0)]:
        hit = pc[((pc.radial_velocity_mps - v).abs() < 0.2) & ((pc.azimuth_deg - az).abs() < 2)]
        assert len(hit) == 1


def test_ddma_gathers_4x_signal_energy_before_demodulation(make_config, make_scene):
    """[TI-DDMA] eq. 10: same scene, same frame time, each DDMA virtual channel
    integrates 768 chirps against TDMA's 192, so the peak over the Doppler-spectrum noise floor
    is 10 log10 4 = 6.02 dB higher. Target on a range and a Doppler bin of both grids."""
    d, t = make_config("ddma", antenna_pattern="isotropic"), \
        make_config("tdma", antenna_pattern="isotropic")
    r0 = 50
    v = 12 * 4 * d.velocity_resolution_mps  # on the 192-point grid, hence the 768-point one
    sc = make_scene([[r0 * d.range_resolution_m, 0, 0, v, 1000.0]])  # high SNR per channel
    rng = np.random.default_rng(5)
    gains = []
    for _ in range(4):
        out = {}
        for cfg in (d, t):
            rf = range_fft(radarsim.simulate_frame(cfg, sc, rng), window("hann", cfg.n_samples))
            if cfg.mimo == "ddma":
                spec = doppler_fft(rf, window("hann", cfg.n_chirps))  # (768, R, B)
                peak = np.sort(np.abs(spec[:, 0, r0]) ** 2)[-4:].mean()  # the four Tx lines
            else:
                rf = rf.reshape(-1, cfg.n_tx, cfg.n_rx, rf.shape[-1])
                spec = doppler_fft(rf, window("hann", rf.shape[0]))  # (192, S, R, B)
                peak = (np.abs(spec[:, :, 0, r0]) ** 2).max(axis=0).mean()
                spec = spec[:, 0]
            floor = np.mean(np.abs(spec[:, 0, 120:180]) ** 2)  # noise-only range bins
            out[cfg.mimo] = 10 * np.log10(peak / floor)
        gains.append(out["ddma"] - out["tdma"])
    assert np.mean(gains) == pytest.approx(10 * np.log10(4), abs=0.5)


def test_demodulation_raises_noise_floor_by_selection_bias(make_config):
    """Picking the strongest n_tx of n_subbands sub-bands per noise-only bin biases the
    demodulated noise power up: about 0.6 dB for 4 of 6, and within 0.1 dB of the
    independent numpy model of the demodulation (0.64 dB; either mean over ~1e6 cells)."""
    cfg = make_config("ddma")
    adc = radarsim.simulate_frame(cfg, radarsim.Scatterers.empty(), np.random.default_rng(6))
    raw = doppler_fft(range_fft(adc, window("hann", cfg.n_samples)),
                      window("hann", cfg.n_chirps))
    power, _, _ = pipeline.detection_map(cfg, adc)
    bias_db = 10 * np.log10(power[1:].mean() / (12 * np.mean(np.abs(raw[:, :, 1:]) ** 2)))
    assert 0.3 < bias_db < 0.9
    model = _ddma_noise_model_map(np.random.default_rng(7), 191)
    hann = np.hanning(cfg.n_chirps + 1)[:-1]  # E|X|^2 of the model spectrum: 2 sum(hann^2)
    model_db = 10 * np.log10(model.mean() / (12 * 2 * np.sum(hann ** 2)))
    assert bias_db == pytest.approx(model_db, abs=0.1)


@pytest.mark.slow
def test_detection_snr_gain_ddma_over_tdma(make_config, make_scene):
    """snr_db of the same target in the same frame time: 6.02 dB of extra energy minus the
    demodulated noise-floor bias, about 5.4 dB (accepted 4.9 to 6.5)."""
    d, t = make_config("ddma", antenna_pattern="isotropic"), \
        make_config("tdma", antenna_pattern="isotropic")
    rng = np.random.default_rng(8)
    gains = []
    for _ in range(60):
        tg = [rng.uniform(20, 200), rng.uniform(-45, 45), 0.0, rng.uniform(-9, 9), 30.0]
        sc = scene_at_snr(d, make_scene, tg)
        snr = [best_near(pipeline.process_frame(c, radarsim.simulate_frame(c, sc, rng)),
                         tg[0]).snr_db for c in (d, t)]
        gains.append(snr[0] - snr[1])
    assert 4.9 <= np.median(gains) <= 6.5


def _exceedances(power, axis, cf, looks):
    """CFAR exceedances of a square-law map (the generic `cfar_map`) and its cell count."""
    noise = cfar_map(power, axis, cf.guard_cells, cf.window_cells, cf.mode, cf.os_rank,
                     cf.training_stride)
    return np.count_nonzero(power > cf.scale(looks) * noise), power.size


@pytest.mark.parametrize("n_frames, tol", [pytest.param(12, 0.25, marks=pytest.mark.slow),
                                           (3, 0.4)], ids=["12_frames", "3_frames"])
def test_noise_only_tdma_false_alarms_match_design_pfa(make_config, n_frames, tol):
    """TDMA cells are sums of 16 exponential looks, the case the threshold is designed for: on
    noise-only frames the exceedance count is Pfa x cells x frames = 1e-3 x 36 672 x 12 = 440,
    within 25 % (several binomial sigma); the fast counterpart, 3 frames (110 expected),
    within 40 % (4 binomial sigma)."""
    cfg = make_config("tdma")
    proc = pipeline.ProcessingConfig().replace(cfar_pfa=1e-3)
    rng = np.random.default_rng(9)
    hits = cells = 0
    for _ in range(n_frames):
        power, looks, axis = pipeline.detection_map(
            cfg, radarsim.simulate_frame(cfg, radarsim.Scatterers.empty(), rng), proc)
        h, c = _exceedances(power[1:], axis, proc.cfar, looks)  # bin 0 (DC) is never searched
        hits, cells = hits + h, cells + c
    assert (1 - tol) * 1e-3 * cells < hits < (1 + tol) * 1e-3 * cells


def _ddma_noise_model_map(rng, n_range, n_sb=6, n_dop=128, n_tx=4, n_rx=4, n_az=48):
    """Independent model of the demodulated DDMA noise map ([TI-DDMA] table 11), numpy only:
    white complex Gaussian slow time per range bin and Rx, Hann window, Doppler FFT; per Doppler
    bin of a sub-band the largest cyclic sum of n_tx sub-band energies picks Tx1's band; the
    horizontal Tx (the first three of Tx1, Tx3, Tx4, Tx2) x Rx give 12 elements at positions
    0..11, zero-padded to n_az. Returns (n_range, n_az, n_dop) power."""
    n_c = n_sb * n_dop
    x = rng.standard_normal((n_range, n_rx, n_c)) + 1j * rng.standard_normal((n_range, n_rx, n_c))
    spec = np.fft.fft(x * np.hanning(n_c + 1)[:-1], axis=-1).reshape(n_range, n_rx, n_sb, n_dop)
    s = (np.abs(spec) ** 2).sum(axis=1)  # (B, N, D)
    z = sum(np.roll(s, -m, axis=1) for m in range(n_tx))
    band = (np.argmax(z, axis=1)[:, None, :] + np.arange(3)[None, :, None]) % n_sb  # (B, 3, D)
    rows = np.take_along_axis(spec, band[:, None], axis=2)  # (B, Rx, 3, D)
    elements = rows.transpose(0, 3, 2, 1).reshape(n_range, n_dop, 12)  # position 4 p + rx
    return np.abs(np.fft.fft(elements, n=n_az, axis=-1)).transpose(0, 2, 1) ** 2


@pytest.mark.parametrize("n_frames, tol", [pytest.param(3, 0.25, marks=pytest.mark.slow),
                                           (1, 0.45)], ids=["3_frames", "1_frame"])
def test_noise_only_ddma_false_alarms_match_noise_model(make_config, n_frames, tol):
    """DDMA cells come out of the empty-band selection (the strongest 4 of 6 sub-bands), so
    they are not the exponential cells Rohling's threshold assumes. On noise-only frames the
    chain's exceedance count matches the same CFAR on an independent model of the
    demodulated noise (3 frames: within 25 %, about 5 sigma of the difference of two counts of
    ~2 700 with the correlated azimuth bins; the fast counterpart, 1 frame: 45 %, the same
    5 sigma of counts a third as large), and stays at or below the design Pfa x cells."""
    cfg = make_config("ddma")
    proc = pipeline.ProcessingConfig().replace(cfar_pfa=1e-3)
    rng = np.random.default_rng(9)
    hits = cells = 0
    for _ in range(n_frames):
        power, looks, axis = pipeline.detection_map(
            cfg, radarsim.simulate_frame(cfg, radarsim.Scatterers.empty(), rng), proc)
        h, c = _exceedances(power[1:], axis, proc.cfar, looks)
        hits, cells = hits + h, cells + c
    model_hits, model_cells = _exceedances(_ddma_noise_model_map(rng, n_frames * 191), 2,
                                           proc.cfar, 1)
    model_rate = model_hits / model_cells
    assert abs(hits / cells - model_rate) < tol * model_rate
    assert hits < (1 + tol) * 1e-3 * cells


def test_training_stride_restores_design_pfa_on_hann_spectra(make_config):
    """Contiguous training cells of a Hann-windowed spectrum are correlated (power correlation
    4/9 at lag 1): the OS estimate spreads more and false alarms exceed the design; every other
    bin (stride 2, the default) restores it (TDMA, 16-look cells, Pfa 1e-3)."""
    cfg = make_config("tdma")
    rng = np.random.default_rng(19)
    frames = [radarsim.simulate_frame(cfg, radarsim.Scatterers.empty(), rng) for _ in range(8)]
    rates = {}
    for stride in (1, 2):
        proc = pipeline.ProcessingConfig().replace(cfar_pfa=1e-3, cfar_training_stride=stride)
        cf = proc.cfar
        hits = cells = 0
        for adc in frames:
            power, looks, axis = pipeline.detection_map(cfg, adc, proc)
            noise = cfar_map(power[1:], axis, cf.guard_cells, cf.window_cells, cf.mode,
                             cf.os_rank, stride)
            hits += np.count_nonzero(power[1:] > cf.scale(looks) * noise)
            cells += power[1:].size
        rates[stride] = hits / cells
    assert rates[1] > 1.2e-3
    assert 0.8e-3 < rates[2] < 1.25e-3


@pytest.mark.parametrize("preset", REGISTRY)
def test_noise_only_point_cloud_bounded_by_design(preset, make_config):
    """End to end, local-maximum selection can only remove CFAR exceedances: false detections
    per frame stay below Pfa x cells (DDMA: 1e-6 x 1.18e6 = 1.2; TDMA: 1e-6 x 3.7e4)."""
    cfg = make_config(preset)
    rng = np.random.default_rng(10)
    n = [len(pipeline.process_frame(cfg, radarsim.simulate_frame(
        cfg, radarsim.Scatterers.empty(), rng))) for _ in range(6)]
    power, _, _ = pipeline.detection_map(cfg, radarsim.simulate_frame(
        cfg, radarsim.Scatterers.empty(), rng))
    assert np.mean(n) <= 1.5 * max(1.0, 1e-6 * power.size)


@pytest.mark.parametrize("preset", REGISTRY)
def test_point_cloud_columns_and_geometry(preset, make_config, make_scene):
    cfg = make_config(preset)
    sc = scene_at_snr(cfg, make_scene, [[40, 20, 5, -5, 30]])
    pc = pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, sc, np.random.default_rng(0)))
    assert list(pc.columns) == pipeline.POINT_CLOUD_COLUMNS
    r, az, el = pc.range_m, np.radians(pc.azimuth_deg), np.radians(pc.elevation_deg)
    np.testing.assert_allclose(np.hypot(np.hypot(pc.x_m, pc.y_m), pc.z_m), r, rtol=1e-9)
    np.testing.assert_allclose(np.arctan2(pc.y_m, pc.x_m), az, atol=1e-9)
    np.testing.assert_allclose(pc.z_m, r * np.sin(el), atol=1e-9)


def test_empty_frame_gives_empty_table_with_columns(make_config):
    cfg = make_config("ddma")
    pc = pipeline.process_frame(cfg, np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples),
                                              np.int16))
    assert isinstance(pc, pd.DataFrame) and pc.empty
    assert set(pipeline.POINT_CLOUD_COLUMNS) <= set(pc.columns)


@pytest.mark.parametrize("bad, match", [
    (lambda c: np.zeros((c.n_chirps, c.n_rx, c.n_samples), np.float32), "int16"),
    (lambda c: np.zeros((c.n_chirps, c.n_rx, c.n_samples - 2), np.int16), "shape"),
    (lambda c: [[0]], "numpy.ndarray"),
])
def test_bad_frame_rejected(bad, match, make_config):
    cfg = make_config("ddma")
    with pytest.raises(ValueError, match=match):
        pipeline.process_frame(cfg, bad(cfg))


def test_config_that_does_not_match_frame_rejected(make_config):
    frame = np.zeros((768, 4, 384), np.int16)
    with pytest.raises(ValueError, match="does not match the config"):
        pipeline.process_frame(make_config("ddma", n_rx=3), frame)
    with pytest.raises(ValueError, match="RadarConfig"):
        pipeline.process_frame({"mimo": "ddma"}, frame)
    with pytest.raises(ValueError, match="ProcessingConfig"):
        pipeline.process_frame(make_config("ddma"), frame, proc={"cfar": "os"})


@pytest.mark.parametrize("preset", REGISTRY)
def test_doppler_azimuth_map_peaks_at_target(preset, make_config, make_scene):
    """The plotted map puts a target at its (unwrapped for DDMA) velocity and sin(az)."""
    cfg = make_config(preset, antenna_pattern="isotropic")
    r_bin, v, az = 60, -6.0, 15.0
    sc = scene_at_snr(cfg, make_scene, [[r_bin * cfg.range_resolution_m, az, 0, v, 35]])
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(3))
    vel, sin_az, p_db = pipeline.doppler_azimuth_map(cfg, adc, r_bin)
    i, j = np.unravel_index(np.argmax(p_db), p_db.shape)
    assert vel[i] == pytest.approx(v, abs=2 * cfg.velocity_resolution_mps)
    assert sin_az[j] == pytest.approx(np.sin(np.radians(az)), abs=2 / 48)
    with pytest.raises(ValueError, match="range_bin"):
        pipeline.doppler_azimuth_map(cfg, adc, cfg.n_range_bins)


@pytest.mark.parametrize("preset", REGISTRY)
@pytest.mark.parametrize("mode", ["os", "ca", "cago", "caso"])
def test_every_cfar_mode_detects_a_target(mode, preset, make_config, make_scene):
    """Each CFAR mode of [TI-DPC], with its Pfa-derived threshold, finds a 25 dB target and
    stays quiet elsewhere (a handful of false alarms at most)."""
    cfg = make_config(preset, antenna_pattern="isotropic")
    proc = pipeline.ProcessingConfig().replace(cfar_mode=mode)
    sc = scene_at_snr(cfg, make_scene, [[70, -15, 0, 6.0, 25]])
    pc = pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, sc, np.random.default_rng(21)),
                                proc)
    best = best_near(pc, 70)
    assert best is not None and best.radial_velocity_mps == pytest.approx(6.0, abs=0.11)
    assert len(pc) <= 5
