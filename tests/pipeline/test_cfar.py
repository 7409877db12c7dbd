"""CFAR threshold design and kernels against Rohling / Richards (design.md section 8)."""
import numpy as np
import pytest
from scipy import ndimage

from pipeline import threads
from pipeline.cfar import (
    CFAR_MODES,
    candidate_cfar,
    cfar_map,
    cfar_peaks,
    cfar_scale,
    noise_estimate,
    noise_mean_factor,
    pfa_numeric,
    pfa_of_scale,
    rohling_os_pfa,
)
from pipeline.kernels import local_max_mask


def test_rohling_os_reference_values():
    # design.md 8 / Rohling 1983: N=20, k=15, a=6.857 -> 1e-3; N=24, k=18, Pfa=1e-6 -> a=16.29.
    assert rohling_os_pfa(6.857, 20, 15) == pytest.approx(1e-3, rel=2e-3)
    assert cfar_scale(1e-3, "os", 20, 15) == pytest.approx(6.857, abs=2e-3)
    assert cfar_scale(1e-6, "os", 24, 18) == pytest.approx(16.29, abs=5e-3)


@pytest.mark.parametrize("n, k, a", [(16, 12, 10.0), (24, 18, 20.0), (32, 8, 5.0)])
def test_numeric_os_pfa_equals_rohling_closed_form(n, k, a):
    assert pfa_numeric(a, "os", n, k) == pytest.approx(rohling_os_pfa(a, n, k), rel=1e-6)
    assert pfa_of_scale(a, "os", n, k) == pytest.approx(rohling_os_pfa(a, n, k), rel=1e-12)


def test_numeric_ca_pfa_equals_closed_form():
    assert pfa_numeric(12.0, "ca", 16) == pytest.approx((1 + 12.0 / 16) ** -16, rel=1e-6)


def test_ca_cfar_closed_form():
    # design.md 8 / Richards eq. 6.167: Pfa = (1 + a/N)^-N; N=24, Pfa=1e-6 -> a=18.68.
    assert cfar_scale(1e-6, "ca", 24) == pytest.approx(18.68, abs=5e-3)
    assert cfar_scale(1e-4, "ca", 16) == pytest.approx(16 * (1e-4 ** (-1 / 16) - 1), rel=1e-6)


def test_os_noise_mean_factor_is_harmonic_sum():
    # E[X_(k) of N exponentials] = sum_{i=N-k+1}^{N} 1/i (David & Nagaraja).
    assert noise_mean_factor("os", 24, 18) == pytest.approx(sum(1 / i for i in range(7, 25)),
                                                            rel=1e-6)
    assert noise_mean_factor("ca", 24) == pytest.approx(1.0, rel=1e-6)


@pytest.mark.parametrize("pfa, n_trials", [
    pytest.param(1e-3, 400_000, marks=pytest.mark.slow, id="1e-3"),
    pytest.param(1e-2, 40_000, id="1e-2"),  # the fast counterpart: 10x fewer draws
])
@pytest.mark.parametrize("looks", [1, 8])
@pytest.mark.parametrize("mode", list(CFAR_MODES))
def test_design_pfa_matches_monte_carlo(mode, looks, pfa, n_trials):
    """Draw homogeneous L-look noise, apply alpha(Pfa): the false-alarm fraction is binomial
    around the design Pfa (3.5 sigma bound: 11 % of 1e-2 with 40 000 draws, 17 % of 1e-3 with
    400 000). A mode on another statistic than the square-law sum (TI's log modes) gets cells
    of its own `combine_looks` of L exponential looks."""
    rng = np.random.default_rng(7)
    n_train, k = 16, 12
    alpha = cfar_scale(pfa, mode, n_train, k, looks)
    m = CFAR_MODES[mode]
    if m.sums_looks:
        cells = rng.gamma(looks, size=(n_trials, n_train + 1))
    else:
        cells = np.concatenate([m.combine_looks(rng.exponential(
            size=(n_trials // 8, n_train + 1, looks)).astype(np.float32), axis=-1)
            for _ in range(8)])
    y = noise_estimate(cells[:, :16].copy(), 8, mode, k)
    rate = np.mean(cells[:, 16] > alpha * y)
    sigma = np.sqrt(pfa * (1 - pfa) / n_trials)
    assert abs(rate - pfa) < 3.5 * sigma


@pytest.mark.parametrize("stride", [1, 2, 3])
@pytest.mark.parametrize("mode", list(CFAR_MODES))
def test_candidate_cfar_equals_full_map(mode, stride):
    rng = np.random.default_rng(1)
    power = rng.exponential(size=(5, 7, 64)).astype(np.float32)
    full = cfar_map(power, axis=2, guard_cells=2, window_cells=6, mode=mode, os_rank=9,
                    stride=stride)
    cand = tuple(rng.integers(0, s, 200) for s in power.shape)
    sparse = candidate_cfar(power, cand, 2, 2, 6, mode, 9, stride)
    np.testing.assert_allclose(sparse, full[cand], rtol=1e-5)


@pytest.mark.parametrize("mode", list(CFAR_MODES))
def test_candidate_cfar_window_longer_than_axis(mode):
    """A short Doppler axis (small test profiles) wraps the window several times, like
    scipy.ndimage's wrap mode."""
    rng = np.random.default_rng(4)
    power = rng.exponential(size=(3, 10))
    full = cfar_map(power, axis=1, guard_cells=2, window_cells=6, mode=mode, os_rank=9,
                    stride=2)
    cand = (np.repeat(np.arange(3), 10), np.tile(np.arange(10), 3))
    np.testing.assert_allclose(candidate_cfar(power, cand, 1, 2, 6, mode, 9, 2),
                               full[cand], rtol=1e-6)


def test_candidate_cfar_wraps_cyclically():
    power = np.ones((1, 32))
    power[0, 30] = 100.0  # a training cell of bin 1 across the wrap (offset -3)
    est = candidate_cfar(power, (np.array([0]), np.array([1])), 1, 2, 4, "ca", 1)
    assert est[0] == pytest.approx((100 + 7) / 8)


def test_local_max_matches_ndimage_reference():
    rng = np.random.default_rng(2)
    p = rng.exponential(size=(6, 9, 11))
    mask = local_max_mask(p, {1: True, 2: True})
    cross = np.zeros((1, 3, 3), bool)
    cross[0, 1, :] = cross[0, :, 1] = True
    ref = p == ndimage.maximum_filter(p, footprint=cross, mode="wrap")
    np.testing.assert_array_equal(mask, ref)


def test_local_max_non_cyclic_edges_compare_one_neighbour():
    p = np.array([[5.0, 1.0, 2.0, 0.5]])
    np.testing.assert_array_equal(local_max_mask(p, {1: False}), [[True, False, True, False]])


def test_cfar_scale_rejects_bad_pfa():
    with pytest.raises(ValueError, match="pfa"):
        cfar_scale(1.5, "os", 16, 12)


def test_unknown_mode_rejected():
    with pytest.raises(ValueError, match=r"mode='median' is not one of \['ca', 'cago'"):
        noise_estimate(np.ones((1, 4)), 2, "median", 1)


@pytest.mark.parametrize("mode", list(CFAR_MODES))
def test_candidate_mask_is_a_necessary_condition(mode):
    """A mode's candidate pre-filter never drops a cell its full-map test detects."""
    rng = np.random.default_rng(5)
    power = rng.exponential(size=(4, 6, 64))
    power[1, 2, 10] = 300.0
    alpha = cfar_scale(1e-3, mode, 24, 18)
    hit = power > alpha * cfar_map(power, 2, 2, 12, mode, 18, 2)
    pre = CFAR_MODES[mode].candidate_mask(power, 2, alpha, 18)
    assert pre.shape == power.shape and hit[1, 2, 10]
    assert not np.any(hit & ~pre)


def test_every_ti_average_mode_code_names_a_registered_mode():
    """[TI-DPC] averageMode: 0 CA, 1 CAGO, 2 CASO, 3 OS; one table (radarsim.ti.codes) maps
    the codes onto this registry."""
    from radarsim.ti.codes import CFAR_AVERAGE_MODES

    assert CFAR_AVERAGE_MODES == {0: "ca", 1: "cago", 2: "caso", 3: "os"}
    assert set(CFAR_AVERAGE_MODES.values()) <= set(CFAR_MODES)
    for name, m in CFAR_MODES.items():
        assert m.name == name and m.description
    assert [n for n, m in CFAR_MODES.items() if m.ranked] == ["os"]  # only OS uses os_rank
    # TI's demos run the CA family on the log statistic (pipeline.cfar.log_law), OS as is.
    from pipeline.cfar import ti_log_mode
    assert {c: ti_log_mode(n) for c, n in CFAR_AVERAGE_MODES.items()} == \
        {0: "ti_log_ca", 1: "ti_log_cago", 2: "ti_log_caso", 3: "os"}


def _reference_peaks(power, mode, alpha, guard, window, k, stride, neighbours, first_bin):
    """Every local maximum (`local_max_mask`) at or beyond `first_bin` on axis 1 whose power
    exceeds alpha x the full-map noise estimate (`cfar_map`), C order."""
    mask = local_max_mask(power, {**neighbours, 2: True})
    mask[:, :first_bin] = False
    noise = cfar_map(power, 2, guard, window, mode, k, stride).astype(power.dtype)
    mask &= power > alpha * noise
    cells = np.nonzero(mask)
    return cells, noise[cells]


@pytest.mark.parametrize("order", ["C", "F"])
@pytest.mark.parametrize("mode", list(CFAR_MODES))
@pytest.mark.parametrize("neighbours, first_bin", [({0: True, 1: False}, 1), ({0: True}, 0),
                                                   ({1: False}, 3), ({0: False, 1: True}, 0)])
@pytest.mark.parametrize("guard, window, stride, n_dop", [(2, 12, 2, 64), (1, 6, 1, 16),
                                                          (2, 8, 3, 20)])
def test_cfar_peaks_equals_the_full_map_reference(mode, neighbours, first_bin, guard, window,
                                                 stride, n_dop, order):
    """The detector the chains run (the OS mode's compiled pass, the numpy path of the others)
    gives exactly the cells, noise estimates and peaks of the full-map reference, on maps with
    exact ties (plateaus), targets, and training windows longer than the axis (wrapping more
    than once), in C order and strided (F order: the slot chains' range-Doppler sum is a
    strided view)."""
    rng = np.random.default_rng(n_dop + first_bin)
    power = rng.exponential(size=(5, 7, n_dop)).astype(np.float32)
    power[rng.random(power.shape) < 0.1] = 1.0          # plateaus
    power[2, 3, 5] = power[4, 6, n_dop - 1] = 400.0      # targets, one at the wrap
    power[0, 0, 0] = 400.0
    # Strong plateaus (two equal cells) along each axis: the first cell alone is the maximum.
    power[1, 4, 9:11] = power[2:4, 1, 12] = power[3, 5:7, 14] = 500.0
    power = np.asarray(power, order=order)
    k = max(1, round(1.5 * window))
    alpha = cfar_scale(1e-2, mode, 2 * window, k)
    (a, r, d), noise, peak = cfar_peaks(power, mode, alpha, guard, window, k, stride,
                                        neighbours, first_bin)
    cells, want = _reference_peaks(power, mode, alpha, guard, window, k, stride, neighbours,
                                   first_bin)
    for got, ref in zip((a, r, d), cells):
        np.testing.assert_array_equal(got, ref)
    np.testing.assert_allclose(noise, want, rtol=1e-6 if mode != "os" else 0)
    np.testing.assert_array_equal(peak, power[cells])
    assert a.size >= 4


@pytest.mark.parametrize("mode", ["os", "ca"])
def test_cfar_peaks_in_two_parts_are_the_whole_pass(mode, monkeypatch):
    """The compiled detector's two parts (rows of axis 0 on two threads, forced on any machine)
    joined in C order are the detections, noise estimates and peaks of one pass, bit for bit
    (the numpy path has one pass either way)."""
    rng = np.random.default_rng(7)
    power = rng.exponential(size=(6, 9, 32)).astype(np.float32)
    power[::2, ::3, ::5] = 300.0
    args = (mode, cfar_scale(1e-2, mode, 8, 6), 1, 4, 6, 1, {0: True, 1: False}, 0)
    monkeypatch.setattr(threads, "N_PARTS", 1)
    cells, noise, peak = cfar_peaks(power, *args)
    monkeypatch.setattr(threads, "N_PARTS", 2)
    assert len(threads.spans(power.shape[0])) == 2
    got = cfar_peaks(power, *args)
    assert all(np.array_equal(x, y) for x, y in zip(got[0], cells)) and cells[0].size >= 8
    assert got[1].tobytes() == noise.tobytes() and got[2].tobytes() == peak.tobytes()
