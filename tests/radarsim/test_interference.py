"""FMCW-FMCW interference synthesis against analytic references (DESIGN 6 and 8)."""
from __future__ import annotations

import hashlib
import math

import numpy as np
import pandas as pd
import pytest

import radarsim
from radarsim import interference as itf_mod
from radarsim.config import C_MPS
from radarsim.frontend import IF_LOWPASS_HZ


def _itf(slope=20e12, r=30.0, az_deg=10.0, period=40e-6, ramp=30e-6, offset=1e-6, f0=77e9,
         power_dbm=12.0, gain_dbi=10.0, v=0.0, visible=True):
    a = math.radians(az_deg)
    return itf_mod.Interferers(position_m=[[r * math.cos(a), r * math.sin(a), 0.0]],
                               radial_velocity_mps=[v], tx_gain_dbi=[gain_dbi],
                               start_freq_hz=[f0], slope_hz_per_s=[slope],
                               chirp_period_s=[period], ramp_time_s=[ramp],
                               chirp_offset_s=[offset], tx_power_dbm=[power_dbm],
                               visible=[visible])


@pytest.fixture(scope="module")
def cfg():
    return radarsim.presets.r79_ddma(antenna_pattern="isotropic")


@pytest.mark.parametrize("slope", [20e12, 40e12, -15e12], ids=["20MHz/us", "40MHz/us", "down"])
def test_burst_duration_and_crossing_time(cfg, slope):
    """-3 dB burst length = 2 B_IF / |S_v - S_i| (B_IF the IF corner); the burst is centred on
    the crossing time f_v(t) = f_i(t - tau) solved by hand."""
    f0 = 77.05e9 if slope > 0 else 77.2e9
    itf = _itf(slope=slope, f0=f0, ramp=8e-6 if slope < 0 else 30e-6)
    x = itf_mod.synthesize(cfg, itf, analytic=True).reshape(cfg.n_chirps, cfg.n_rx, -1)[:, 0]
    env = np.abs(x)
    amp = env.max()
    ds = abs(cfg.slope_hz_per_s - slope)
    want = 2 * IF_LOWPASS_HZ / ds * cfg.adc_rate_sps  # samples
    tau = itf.range_m[0] / C_MPS
    fs = cfg.adc_rate_sps
    checked = 0
    half = 0.5 * want / fs
    for c in range(cfg.n_chirps):
        above = np.flatnonzero(env[c] > amp / math.sqrt(2))
        if above.size == 0:
            continue
        # Crossing: f0v + Sv u = f0i + Si (u + T_c - tau - A_m) for the ramp m in flight.
        t_ramp = c * cfg.chirp_period_s
        centre = 0.5 * (above[0] + above[-1])  # the flat Butterworth top: its centre
        t_mid = t_ramp + cfg.adc_start_time_s + centre / fs
        m = math.floor((t_mid - tau - itf.chirp_offset_s[0]) / itf.chirp_period_s[0])
        a_m = itf.chirp_offset_s[0] + m * itf.chirp_period_s[0]
        u = (f0 - cfg.start_freq_hz + slope * (t_ramp - tau - a_m)) / (cfg.slope_hz_per_s - slope)
        t_cross = t_ramp + u
        ramp_lo, ramp_hi = a_m + tau, a_m + tau + itf.ramp_time_s[0]
        adc_lo = t_ramp + cfg.adc_start_time_s
        adc_hi = adc_lo + (cfg.n_samples - 1) / fs
        if t_cross - half < max(ramp_lo, adc_lo) + 2 / fs or \
                t_cross + half > min(ramp_hi, adc_hi) - 2 / fs:
            continue  # burst cut by the ADC window or the interferer's ramp ends
        assert above.size == pytest.approx(want, abs=2)
        assert u == pytest.approx(cfg.adc_start_time_s + centre / fs, abs=1.0 / fs)
        checked += 1
    assert checked >= 20
    bw = itf_mod.burst_windows(cfg, itf)
    assert len(bw) > 0 and bw["crossing_time_s"].notna().all()


def test_received_power_follows_one_way_radar_equation(cfg):
    """In-burst power at the ADC (plateau of the real samples) = P_t G_t G_r lambda^2 /
    ((4 pi R)^2 L) within 0.5 dB; 6 dB per doubling of range (1/R^2, not 1/R^4)."""
    powers = []
    for r in (20.0, 40.0):
        itf = _itf(slope=12e12, r=r)  # slow sweep: long bursts with a flat centre
        x = itf_mod.synthesize(cfg, itf).reshape(cfg.n_chirps, cfg.n_rx, -1)
        xa = np.abs(itf_mod.synthesize(cfg, itf, analytic=True)).reshape(x.shape)
        plateau = xa > 0.99 * xa.max()
        p_lsb2 = float(np.mean(x[plateau].astype(np.float64) ** 2))
        p_w = p_lsb2 / cfg.adc_code_per_sqrt_w ** 2
        lam = cfg.wavelength_m
        friis = (1e-3 * 10 ** (12 / 10) * 10 ** (10 / 10) * 10 ** (cfg.rx_antenna_gain_dbi / 10)
                 * lam ** 2 / ((4 * math.pi * r) ** 2 * 10 ** (cfg.system_loss_db / 10)))
        assert 10 * math.log10(p_w / friis) == pytest.approx(0.0, abs=0.5)
        powers.append(p_w)
    assert 10 * math.log10(powers[0] / powers[1]) == pytest.approx(6.02, abs=0.5)


def test_same_slope_interferer_is_a_tone_at_its_one_way_range(cfg):
    """Equal slope and period: f_d = S (Delta + tau) constant, a ghost in range bin
    (Delta + tau) c / 2 / dR instead of a raised floor."""
    offset = 0.3e-6
    itf = _itf(slope=cfg.slope_hz_per_s, period=cfg.chirp_period_s,
               ramp=cfg.ramp_end_time_s, offset=offset, r=20.0)
    x = itf_mod.synthesize(cfg, itf).reshape(cfg.n_chirps, cfg.n_rx, -1)
    spec = np.abs(np.fft.rfft(x[:, 0], axis=-1)).mean(axis=0)
    want_bin = cfg.slope_hz_per_s * (offset + 20.0 / C_MPS) / cfg.adc_rate_sps * cfg.n_samples
    assert int(np.argmax(spec[1:]) + 1) == pytest.approx(want_bin, abs=1)


def test_same_slope_out_of_band_makes_no_burst(cfg):
    """Equal slope, offset 10 us: f_d = S (Delta + tau) = 89 MHz, far outside the IF band."""
    itf = _itf(slope=cfg.slope_hz_per_s, period=cfg.chirp_period_s,
               ramp=cfg.ramp_end_time_s, offset=10e-6)
    assert len(itf_mod.burst_windows(cfg, itf)) == 0
    assert not itf_mod.synthesize(cfg, itf).any()
    assert math.isnan(itf_mod.interference_to_noise_db(cfg, itf))


def test_blocked_path_and_back_lobe_are_silent(cfg):
    truth = pd.DataFrame({
        "actor_id": [0, 1], "x_radar_m": [40.0, 20.0], "y_radar_m": [0.0, 0.0],
        "z_radar_m": [0.25, 1.5], "yaw_radar_deg": [180.0, 0.0], "vx_radar_mps": [0.0, 0.0],
        "vy_radar_mps": [0.0, 0.0], "length_m": [5.0, 16.0], "width_m": [2.0, 2.55],
        "height_m": [1.5, 4.0]})
    eq = pd.DataFrame([{c: 0.0 for c in itf_mod.EQUIPMENT_COLUMNS}])
    eq = eq.assign(actor_id=0, mount_x_m=2.3, mount_z_m=0.5, start_freq_hz=77e9,
                   slope_hz_per_s=20e12, chirp_period_s=40e-6, ramp_time_s=30e-6,
                   tx_power_dbm=12.0, antenna_gain_dbi=10.0, pattern_exponent_az=1.0,
                   pattern_exponent_el=1.0)
    blocked = itf_mod.interferers_from_truth(cfg, truth, eq)
    assert len(blocked) == 1 and not blocked.visible[0]
    clear = itf_mod.interferers_from_truth(cfg, truth[truth.actor_id == 0], eq)
    assert clear.visible[0] and clear.range_m[0] == pytest.approx(37.7, abs=0.01)
    # The same car facing away: its radar's back lobe has no gain.
    away = itf_mod.interferers_from_truth(cfg, truth[truth.actor_id == 0]
                                          .assign(yaw_radar_deg=0.0), eq)
    assert not away.visible[0]
    assert itf_mod.received_power_w(cfg, blocked)[0] == 0.0


def test_frames_without_interferers_are_bit_identical_to_main():
    """No interferer, front-end terms off: the same bits as before this change (hash taken
    on main before the interference model existed)."""
    cfg = radarsim.presets.r79_ddma()
    sc = radarsim.Scatterers(position_m=[[50.0, 5.0, 0.5], [12.0, -3.0, 0.0],
                                         [120.0, 30.0, 1.0]],
                             velocity_mps=[[-20.0, 0.0, 0.0], [3.0, 1.0, 0.0], [10.0, 0, 0]],
                             rcs_m2=[10.0, 1.0, 30.0])
    a = radarsim.simulate_frame(cfg, sc, np.random.default_rng(123))
    b = radarsim.simulate_frame(cfg, sc, np.random.default_rng(123),
                                itf_mod.Interferers.empty())
    assert np.array_equal(a, b)
    assert hashlib.sha256(a.tobytes()).hexdigest() == \
        "48c72b59703e593740193c0eb98dde1b64e1b01adc43082e3b1d248b101eb592"


def test_dc_offset_and_leakage_terms():
    cfg = radarsim.presets.r79_ddma()
    sc = radarsim.Scatterers(position_m=np.zeros((0, 3)), velocity_mps=np.zeros((0, 3)),
                             rcs_m2=[])
    a = radarsim.simulate_frame(cfg, sc, np.random.default_rng(1))
    b = radarsim.simulate_frame(cfg.replace(adc_dc_offset_lsb=200.0), sc,
                                np.random.default_rng(1))
    diff = b.astype(np.int32) - a  # float32 rounding may move a tie by one LSB
    assert np.abs(diff - 200).max() <= 1 and diff.mean() == pytest.approx(200, abs=0.01)
    c = radarsim.simulate_frame(cfg.replace(tx_leakage_dbfs=-30.0), sc,
                                np.random.default_rng(1))
    lk = (c.astype(float) - a).mean(axis=(0, 1))
    # A tone from a 0.1 m path: beat 2 S d / c (5.9 kHz, nearly DC over the chirp), phase
    # -4 pi d / lambda, identical on every chirp and Rx.
    t_n = cfg.adc_start_time_s + np.arange(cfg.n_samples) / cfg.adc_rate_sps
    want = 32767 * 10 ** (-30 / 20) * np.cos(2 * np.pi * 2 * cfg.slope_hz_per_s * 0.1 / C_MPS
                                             * t_n - 4 * np.pi * 0.1 / cfg.wavelength_m)
    assert np.abs(lk - want).max() < 1.0


@pytest.mark.parametrize("kw, match", [
    (dict(ramp=50e-6, period=40e-6), "ramp_time_s must be <= chirp_period_s"),
    (dict(period=0.0), "must be > 0"),
    (dict(r=0.01), "range must be >= 0.1 m"),
])
def test_interferers_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        _itf(**kw)


@pytest.mark.parametrize("kw, match", [
    (dict(adc_dc_offset_lsb=40000.0), "adc_dc_offset_lsb"),
    (dict(tx_leakage_dbfs=3.0), "tx_leakage_dbfs"),
])
def test_front_end_term_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        radarsim.presets.r79_ddma(**kw)
