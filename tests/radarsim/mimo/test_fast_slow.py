"""The fast/slow chirp scheme's transmit side ([TI-VEXT] section 3): the two chirp periods,
their timing in the frame, the promised span and the validation of every rule."""
import numpy as np
import pytest

import radarsim
from radarsim.mimo import MIMO_SCHEMES, TdmaScheme, register_scheme
from radarsim.mimo.fast_slow import FastSlowScheme, hypothesis_separation_bins

LAMBDA_M = 299_792_458.0 / 77e9


@pytest.fixture
def fast_slow():
    return radarsim.presets.r79("fast_slow")


def test_r79_preset_periods_and_span(fast_slow):
    """Mean chirp 23.81 us (the R79 frame time, 768 chirps, 4 Tx); T_s / T_f = 6 / 5 as TI's
    SRR (70.8 / 59 us): T_f = 2 x 23.81 / 2.2 = 21.645 us, T_s = 25.975 us, so
    V_f = lambda / (16 T_f) = 11.242 m/s and the unfolded span 4 V_f = 44.97 m/s covers the
    R79 span +/-40.9 m/s (design.md section 8)."""
    cfg = fast_slow
    sets = cfg.scheme.chirp_sets(cfg)
    assert (cfg.n_chirps, cfg.n_tx, cfg.frame_time_s) == (768, 4, pytest.approx(18.286e-3,
                                                                              rel=1e-4))
    assert sets.fast_period_s == pytest.approx(21.6455e-6, rel=1e-5)
    assert sets.slow_period_s / sets.fast_period_s == pytest.approx(70.8 / 59, rel=1e-12)
    assert (sets.fast, sets.slow, sets.n_doppler_bins) == (slice(0, 384), slice(384, 768), 96)
    v_f = LAMBDA_M / (16 * sets.fast_period_s)
    assert cfg.scheme.native_max_velocity_mps(cfg) == pytest.approx(v_f, rel=1e-12)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(4 * v_f, rel=1e-12)
    assert cfg.max_unambiguous_velocity_mps >= 40.9
    assert cfg.scheme.velocity_failure_step_mps(cfg) == pytest.approx(2 * v_f)
    # One set's Doppler bin: lambda / (2 x 384 T_f).
    assert cfg.velocity_resolution_mps == pytest.approx(LAMBDA_M / (768 * sets.fast_period_s))
    idle_f, idle_s = cfg.scheme.idle_times_s(cfg)
    assert (idle_f + idle_s) / 2 == pytest.approx(cfg.idle_time_s, rel=1e-9)
    assert idle_f == pytest.approx(2.8355e-6, rel=1e-4) and idle_s > idle_f


def test_chirp_timing_blocks(fast_slow):
    """Ramp starts advance by T_f through the fast block, then by T_s; the reference time
    is the middle of the burst (first and last ramp start symmetric about 0)."""
    cfg = fast_slow
    sets = cfg.scheme.chirp_sets(cfg)
    timing = cfg.scheme.chirp_timing(cfg)
    step = np.diff(timing.ramp_start_s)
    np.testing.assert_allclose(step[:383], sets.fast_period_s, rtol=1e-9)
    np.testing.assert_allclose(step[384:], sets.slow_period_s, rtol=1e-9)
    assert step[383] == pytest.approx(sets.fast_period_s)  # last fast chirp, then the slow set
    assert timing.ramp_start_s[0] == 0.0
    assert timing.t_c_s[0] == pytest.approx(-timing.t_c_s[-1], rel=1e-12)
    np.testing.assert_allclose(np.diff(timing.t_c_s), step)
    flipped = FastSlowScheme("x", "", slow_first=True)
    s2 = flipped.chirp_sets(cfg)
    assert (s2.fast, s2.slow) == (slice(384, 768), slice(0, 384))
    assert np.diff(flipped.chirp_timing(cfg).ramp_start_s)[0] == pytest.approx(sets.slow_period_s)


@pytest.mark.parametrize("name", ["ddma", "tdma", "bpm", "ddma_classic"])
def test_uniform_schemes_keep_their_timing_bit_for_bit(name):
    """The per-chirp timing hook reproduces the uniform formulas exactly (bit-identical
    frames for every other scheme)."""
    cfg = radarsim.presets.r79(name)
    c = np.arange(cfg.n_chirps)
    timing = cfg.scheme.chirp_timing(cfg)
    assert np.array_equal(timing.ramp_start_s, c * cfg.chirp_period_s)
    assert np.array_equal(timing.t_c_s, (c - (cfg.n_chirps - 1) / 2) * cfg.chirp_period_s)


def test_transmit_code_is_tdma_in_each_set(fast_slow):
    """Each set is whole TDMA cycles over tx_order (1, 3, 4, 2): every Tx fires 96 chirps per
    set, one Tx per chirp."""
    code = fast_slow.scheme.transmit_code(fast_slow)
    assert np.all(code.gain.sum(axis=0) == 1) and np.all(code.phase_rad == 0)
    for sl in (slice(0, 384), slice(384, 768)):
        assert np.all(code.gain[:, sl].sum(axis=1) == 96)
    assert [int(np.argmax(code.gain[:, c])) + 1 for c in range(384, 388)] == [1, 3, 4, 2]


def test_echo_aliases_where_each_period_puts_it(fast_slow, make_scene):
    """Front end with the scheme's timing: a target at v lands in the fast set's per-Tx
    Doppler bin -2 v / lambda x 96 x 4 T_f (mod 96) and in the slow set's at 4 T_s."""
    import pipeline
    from pipeline.mimo.fast_slow import fast_slow_maps, slow_bin_of
    cfg = fast_slow.replace(antenna_pattern="isotropic")
    sets = cfg.scheme.chirp_sets(cfg)
    v, r_bin = -31.7, 50
    sc = make_scene([[r_bin * cfg.range_resolution_m, 10.0, 0.0, v, 5.0]])
    adc = radarsim.simulate_frame(cfg, sc, np.random.default_rng(1))
    maps = fast_slow_maps(cfg, adc, pipeline.ProcessingConfig())
    for power, period in ((maps.fast_power, sets.fast_period_s),
                          (maps.slow_power, sets.slow_period_s)):
        want = slow_bin_of(np.array(v), cfg.wavelength_m, 4 * period, 96)
        got = np.argmax(power[r_bin])
        assert min(abs(got - want), 96 - abs(got - want)) <= 0.5


def test_chinese_remainder_span():
    """T_s / T_f = 6 / 5: 2 V_f = 6 u and 2 V_s = 5 u, so the alias pair repeats after
    lcm = 30 u = 5 fast spans: candidates up to 4 spans apart never coincide, 5 do. So
    unfold_factor 5 is the largest this ratio unfolds; 6 is refused."""
    assert hypothesis_separation_bins(1.2, 96, 5) == pytest.approx(19.2)
    assert hypothesis_separation_bins(1.2, 96, 6) == pytest.approx(0.0, abs=1e-9)
    assert hypothesis_separation_bins(1.25, 96, 4) == pytest.approx(24.0)  # 5 / 4: p = 4
    assert hypothesis_separation_bins(1.25, 96, 5) == pytest.approx(0.0, abs=1e-9)
    assert hypothesis_separation_bins(1.2, 96, 1) == np.inf


# ------------------------------------------------------------------------------ validation
@pytest.fixture
def registered():
    added = []

    def _reg(scheme):
        register_scheme(scheme)
        added.append(scheme.name)
        return scheme.name
    yield _reg
    for name in added:
        del MIMO_SCHEMES[name]


def test_ambiguous_ratio_refused(registered):
    name = registered(FastSlowScheme("fs_ratio_15", "", slow_period_ratio=1.5))
    with pytest.raises(ValueError, match=r"slow_period_ratio=1\.5 makes the unfolding ambiguous "
                                         r"over unfold_factor=4 .* 0 slow Doppler bins apart, "
                                         r"below the limit of 1 bin"):
        radarsim.presets.r79(name)


def test_span_beyond_the_chinese_remainder_refused(registered):
    name = registered(FastSlowScheme("fs_u6", "", unfold_factor=6))
    with pytest.raises(ValueError, match=r"slow_period_ratio=1\.2 makes the unfolding ambiguous "
                                         r"over unfold_factor=6"):
        radarsim.presets.r79(name)


def test_unequal_sets_refused():
    with pytest.raises(ValueError, match=r"n_chirps=772 must be divisible by 2 x n_tx=8 for "
                                         r"fast_slow \(two chirp sets of equal count"):
        radarsim.presets.r79("fast_slow", n_chirps=772)


def test_fast_chirp_without_idle_refused():
    with pytest.raises(ValueError, match=r"idle_time_s=1e-06 \(mean of the two sets\): the fast "
                                         r"chirp's idle time .* must be > 0"):
        radarsim.presets.r79("fast_slow", idle_time_s=1e-6, chirp_period_s=19.81e-6)


@pytest.mark.parametrize("ratio", [1.0, 0.8, 4.5, float("nan"), True, "1.2"])
def test_ratio_out_of_range_refused(ratio):
    with pytest.raises(ValueError, match=r"slow_period_ratio=.* must be in \(1, 4\]"):
        FastSlowScheme("x", "", slow_period_ratio=ratio)


@pytest.mark.parametrize("factor", [0, 17, 2.0, True])
def test_unfold_factor_out_of_range_refused(factor):
    with pytest.raises(ValueError, match=r"unfold_factor=.* must be an integer in 1\.\.16"):
        FastSlowScheme("x", "", unfold_factor=factor)


def test_slow_first_must_be_bool():
    with pytest.raises(ValueError, match=r"slow_first=1 must be true or false"):
        FastSlowScheme("x", "", slow_first=1)


def test_scheme_is_a_tdma_pair_and_registered():
    assert isinstance(MIMO_SCHEMES["fast_slow"], TdmaScheme)
    assert MIMO_SCHEMES["fast_slow"].name == "fast_slow"
