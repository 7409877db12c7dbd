"""Compiled kernels of `pipeline.kernels` against their numpy definitions, bit for bit (the
chains' outputs must not move when a pass is compiled), and the DDMA demodulation against
[TI-DDMA] table 11 written out independently."""
import contextlib

import numpy as np
import pytest
import scipy.fft

import pipeline.threads as threads
from pipeline.ddma_kernels import (
    azimuth_map,
    ddma_coherent_power,
    ddma_gather,
    ddma_metric,
    ddma_spectra_power,
    fft48_power,
)
from pipeline.kernels import (
    doppler_fft,
    doppler_windowed,
    estimate_angles,
    rx_energy,
    rx_energy_bins,
    slow_time_fft,
)
from pipeline.stages import power_of


def _cube(rng, shape):
    x = (rng.standard_normal(shape) + 1j * rng.standard_normal(shape)).astype(np.complex64)
    x *= rng.choice(np.float32([1e-3, 1.0, 3e4]), size=shape)  # several magnitudes per row
    return x


@pytest.mark.parametrize("shape", [(768, 4, 192), (64, 3, 17), (16, 1, 5)])
def test_rx_energy_equals_power_summed_over_rx_bit_for_bit(shape):
    spec = _cube(np.random.default_rng(0), shape)
    spec[0, 0, 0] = 0
    out = rx_energy(spec)
    assert out.dtype == np.float32 and out.shape == (shape[0], shape[2])
    assert out.tobytes() == power_of(spec).sum(axis=1).tobytes()


def test_doppler_fft_along_chirps_equals_fft_of_transposed_copy_bit_for_bit():
    """The DDMA chain transforms the (chirp, Rx, range) cube along its first axis in place of
    a contiguous (range, Rx, chirp) copy: the same numbers."""
    rf = _cube(np.random.default_rng(1), (96, 4, 40))
    win = np.hanning(96).astype(np.float32)
    ref = scipy.fft.fft(np.ascontiguousarray((rf * win[:, None, None]).transpose(2, 1, 0)),
                        axis=-1)
    got = doppler_fft(rf, win)
    assert np.ascontiguousarray(got.transpose(2, 1, 0)).tobytes() == ref.tobytes()


@pytest.mark.parametrize("n_sb, n_tx, tx_pos", [(6, 4, [0, 1, 2]), (6, 4, [3]), (4, 4, [0, 2]),
                                                (5, 3, [0, 1, 2])])
def test_ddma_gather_reads_each_tx_from_its_subband(n_sb, n_tx, tx_pos):
    """[TI-DDMA] table 11: Tx p of Doppler bin d sits at chirp-bin d + n_dop ((band + p) mod
    N), band the first Tx's sub-band at (d, range bin)."""
    rng = np.random.default_rng(2)
    n_dop, n_rx, n_b = 8, 3, 11
    spec = _cube(rng, (n_sb * n_dop, n_rx, n_b))
    band = rng.integers(0, n_sb, size=(n_dop, n_b))
    tx_pos = np.asarray(tx_pos)
    out = ddma_gather(spec, band, tx_pos, n_sb)
    assert out.shape == (tx_pos.size * n_rx, n_b * n_dop)
    for i, p in enumerate(tx_pos):
        for rx in range(n_rx):
            for b in range(n_b):
                for d in range(n_dop):
                    want = spec[((band[d, b] + p) % n_sb) * n_dop + d, rx, b]
                    assert out[i * n_rx + rx, b * n_dop + d] == want


def _plan(rng, n_az, positions, n_sb=6, n_tx=4):
    """An `AzimuthMap` of Tx positions 0, 1, 2 with random channel coefficients."""
    coef = _cube(rng, (len(positions),)) / np.float32(3e4)
    return azimuth_map(n_sb, n_tx, np.array([0, 1, 2]), np.asarray(positions), coef, n_az)


def _metric_frame(rng, n_sb, n_dop, n_rx, n_b):
    spec = _cube(rng, (n_sb * n_dop, n_rx, n_b))
    energy = rx_energy(spec)
    energy[: 2 * n_dop, 0] = 1.0  # ties between hypotheses
    energy[3 * n_dop + 1, 1] = np.nan
    return spec, energy


def _l1_bound(plan, x):
    """Bound on |X^ - X| of each map column of the demodulated samples x: the pruned FFT's
    longest path has 11 float32 roundings (gather product, twiddle, twiddle product, the
    4-point DFT's 2 sums, the 3-point DFT's sum, difference, constant, product and 2 sums),
    each at most sqrt(2) u of the column's l1 norm (|W| = 1); 16 u of it bounds them all."""
    return 16 * np.finfo(np.float32).eps / 2 * (np.abs(plan.coef[:, None] * x)).sum(axis=0)


@pytest.mark.parametrize("n_az, positions", [(64, np.arange(12)), (48, np.arange(1, 13)),
                                             (48, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 10]),
                                             (48, [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, -1])])
def test_azimuth_map_is_the_gemm_unless_48_bins_of_12_distinct_positions(n_az, positions):
    plan = _plan(np.random.default_rng(7), n_az, positions)
    assert plan.slot.size == 0
    assert not plan.dft.flags.writeable
    assert (plan.dft[:, np.asarray(positions) < 0] == 0).all()


def test_azimuth_map_columns_are_the_steering_vectors_times_coefficients():
    positions = np.random.default_rng(8).permutation(12)
    plan = _plan(np.random.default_rng(8), 48, positions)
    assert np.array_equal(plan.slot, positions)
    want = np.exp(-2j * np.pi * np.outer(np.arange(48), positions) / 48) * plan.coef
    assert np.abs(plan.dft - want).max() < 4 * np.finfo(np.float32).eps


@pytest.mark.parametrize("n", [1, 7, 1024])
def test_fft48_power_is_the_zero_padded_dft_power_within_float32_rounding(n):
    """|X_k|^2 of the 48-point DFT of 12 samples, against the float64 matrix product: within
    the rounding bound of the pruned FFT (`_l1_bound`, propagated through |.|^2)."""
    z = _cube(np.random.default_rng(9), (12, n))
    x = np.exp(-2j * np.pi * np.outer(np.arange(48), np.arange(12)) / 48) @ z.astype(complex)
    got = fft48_power(z)
    assert got.dtype == np.float32 and got.shape == (48, n)
    delta = 16 * np.finfo(np.float32).eps / 2 * np.abs(z).sum(axis=0)
    bound = 2 * np.abs(x) * delta + delta ** 2 + np.finfo(np.float32).eps * np.abs(x) ** 2
    assert (np.abs(got - np.abs(x) ** 2) <= bound).all()


@pytest.mark.parametrize("n_b", [40, 13, 7, 9, 21])
def test_ddma_coherent_power_gemm_is_argmax_gather_gemm_power_bit_for_bit(n_b):
    """Without the pruned FFT the map is the numpy formulation bit for bit, ties and NaN in
    the metric resolved as numpy's argmax (first maximum, first NaN)."""
    rng = np.random.default_rng(3)
    n_sb, n_tx, n_dop, n_rx = 6, 4, 16, 4
    spec, energy = _metric_frame(rng, n_sb, n_dop, n_rx, n_b)
    plan = _plan(rng, 64, np.arange(12))
    power, band = ddma_coherent_power(spec, energy, plan)
    want_band = np.argmax(ddma_metric(energy, n_sb, n_tx), axis=0)
    assert np.array_equal(band, want_band)
    want = power_of(plan.dft @ ddma_gather(spec, want_band, plan.tx_pos, n_sb))
    assert power.tobytes() == want.tobytes()


@pytest.mark.parametrize("n_b", [40, 13, 7, 9, 21])
def test_ddma_coherent_power_fft_is_the_gemm_power_within_float32_rounding(n_b):
    """The pruned FFT map (rows at permuted positions, channel coefficients) against the
    float64 product of the same DFT matrix, within the FFT's rounding bound; the Tx order as
    numpy's argmax."""
    rng = np.random.default_rng(4)
    n_sb, n_tx, n_dop, n_rx = 6, 4, 16, 4
    spec, energy = _metric_frame(rng, n_sb, n_dop, n_rx, n_b)
    plan = _plan(rng, 48, rng.permutation(12))
    assert plan.slot.size
    power, band = ddma_coherent_power(spec, energy, plan)
    assert np.array_equal(band, np.argmax(ddma_metric(energy, n_sb, n_tx), axis=0))
    x = ddma_gather(spec, band, plan.tx_pos, n_sb)
    steer = np.exp(-2j * np.pi * np.outer(np.arange(48), plan.slot) / 48)
    y = np.abs((steer * plan.coef.astype(complex)) @ x) ** 2
    delta = _l1_bound(plan, x)
    bound = 2 * np.sqrt(y) * delta + delta ** 2 + np.finfo(np.float32).eps * y
    assert power.dtype == np.float32 and (np.abs(power - y) <= bound).all()


@pytest.mark.parametrize("n_b", [40, 13, 7, 21])
@pytest.mark.parametrize("n_az", [48, 64])
@pytest.mark.parametrize("inline", [False, True])
def test_ddma_spectra_power_equals_fft_energy_and_map_passes_bit_for_bit(n_b, n_az, inline,
                                                                         monkeypatch):
    """The Doppler FFT, Rx energy and map by range spans (spans of any width, so pocketfft
    batches a different number of columns than over the whole cube) are the three whole passes
    bit for bit, with two parts (on any machine) and with one (`threads.inline`), for the
    pruned FFT map and the GEMM."""
    monkeypatch.setattr(threads, "N_PARTS", 2)
    rng = np.random.default_rng(5)
    n_sb, n_dop, n_rx = 6, 16, 4
    xw = _cube(rng, (n_sb * n_dop, n_rx, n_b))
    plan = _plan(rng, n_az, np.arange(12))
    spec = slow_time_fft(xw.copy())
    energy = rx_energy(spec)
    with threads.inline():
        want = ddma_coherent_power(spec, energy, plan)
    with threads.inline() if inline else contextlib.nullcontext():
        got = ddma_spectra_power(xw, plan)
    assert got[0] is xw and got[0].tobytes() == spec.tobytes()
    assert got[1].tobytes() == energy.tobytes()
    assert got[2].tobytes() == want[0].tobytes() and np.array_equal(got[3], want[1])


def test_rx_energy_bins_fills_only_its_range_bins():
    spec = _cube(np.random.default_rng(6), (32, 3, 19))
    out = np.full((32, 19), -1.0, np.float32)
    rx_energy_bins(spec, out, 5, 12)
    assert out[:, 5:12].tobytes() == rx_energy(spec)[:, 5:12].tobytes()
    assert (out[:, :5] == -1).all() and (out[:, 12:] == -1).all()


@pytest.mark.parametrize("shape", [(96, 4, 41), (24, 4, 3, 41)])
def test_doppler_window_equals_numpy_complex_product_bit_for_bit(shape):
    """The compiled window product of `doppler_fft` is numpy's complex64 x float32 product,
    special values and signed zeros included, on a strided slice (the range FFT's layout)."""
    full = _cube(np.random.default_rng(4), shape[:-1] + (shape[-1] + 1,))
    x = full[..., :-1]
    x[0, 0, ..., 0] = complex(-0.0, -1.0)
    x[1, 1, ..., 1] = complex(np.nan, 1.0)
    x[2, 0, ..., 2] = complex(np.inf, -0.0)
    win = np.hanning(shape[0]).astype(np.float32)
    win[3] = -0.0
    win[4] = np.inf
    with np.errstate(invalid="ignore"):
        ref = scipy.fft.fft(np.multiply(x, win.reshape((-1,) + (1,) * (x.ndim - 1))), axis=0)
        got = doppler_fft(x, win)
    assert got.tobytes() == ref.tobytes()



@pytest.mark.parametrize("split", [False, True])
def test_doppler_windowed_reads_the_first_bins_of_longer_rows(split):
    """With `out` given, `doppler_windowed` of a whole rFFT output (n_b + 1 bins, Nyquist
    included, C-contiguous) is the product of its first n_b bins, as of the strided view."""
    full = _cube(np.random.default_rng(6), (40, 4, 17))
    win = np.hanning(40).astype(np.float32)
    want = np.multiply(full[..., :16], win[:, None, None])
    got = doppler_windowed(full, win, out=np.empty((40, 4, 16), np.complex64), split=split)
    assert got.tobytes() == want.tobytes()


def test_samples_windowed_equals_numpy_casting_product_bit_for_bit():
    """int16 samples (both rails included) times a float32 window, as numpy's multiply with
    dtype=float32 computes it."""
    from pipeline.kernels import samples_windowed, windowed
    x = np.random.default_rng(5).integers(-32768, 32768, (7, 3, 64)).astype(np.int16)
    x[0, 0, :2] = (-32768, 32767)
    win = np.hanning(64).astype(np.float32)
    win[5] = -0.0
    want = np.multiply(x, win, dtype=np.float32)
    assert samples_windowed(x, win, np.empty(x.shape, np.float32)).tobytes() == want.tobytes()
    assert windowed(x, win, np.float32).tobytes() == want.tobytes()


@pytest.mark.parametrize("n", [0, 1, 57])
def test_point_cloud_equals_the_frame_of_a_column_dict(n):
    """`stages.point_cloud` builds the frame pandas builds from a dict of its columns: same
    columns in order, dtypes, values (NaN included), RangeIndex; and the empty cloud is a new
    frame on every call."""
    import pandas as pd

    import radarsim
    from pipeline import ProcessingConfig
    from pipeline.stages import POINT_CLOUD_COLUMNS, empty_cloud, point_cloud
    cfg, proc = radarsim.presets.r79("ddma"), ProcessingConfig()
    g = np.random.default_rng(n)
    rng_pos, vel, az, el, snr = (g.standard_normal(n) for _ in range(5))
    if n:
        az[0] = np.nan
    bins = {"range_bin": g.integers(0, 3, n), "doppler_bin": g.integers(0, 3, n),
            "azimuth_bin": g.integers(0, 48, n).astype(np.intp)}
    got = point_cloud(cfg, proc, rng_pos, vel, az, el, snr, bins)
    order = np.lexsort((bins["azimuth_bin"], bins["doppler_bin"], bins["range_bin"]))
    # A range below 0 m is clamped to 0, as TI's SDK does (these positions are N(0, 1) bins).
    rng_m = np.maximum((rng_pos * cfg.range_resolution_m + vel * radarsim.config.C_MPS
                        / (cfg.slope_hz_per_s * cfg.wavelength_m))
                       - proc.calibration.range_bias_m,
                       0.0)[order]
    az, el, vel, snr = az[order], el[order], vel[order], snr[order]
    want = pd.DataFrame({
        "range_m": rng_m, "azimuth_deg": np.degrees(az), "elevation_deg": np.degrees(el),
        "radial_velocity_mps": vel, "snr_db": snr,
        "x_m": rng_m * np.cos(el) * np.cos(az), "y_m": rng_m * np.cos(el) * np.sin(az),
        "z_m": rng_m * np.sin(el), **{k: v[order] for k, v in bins.items()},
        "saturated": np.zeros(n, dtype=bool)})
    assert list(got.columns) == POINT_CLOUD_COLUMNS
    assert list(got.dtypes) == list(want.dtypes)
    assert got.index.equals(want.index) and isinstance(got.index, pd.RangeIndex)
    for c in POINT_CLOUD_COLUMNS:
        assert got[c].to_numpy().tobytes() == want[c].to_numpy().tobytes(), c
    e1, e2 = empty_cloud(), empty_cloud()
    assert e1 is not e2 and list(e1.columns) == POINT_CLOUD_COLUMNS and len(e1) == 0
    e1["extra"] = e1["range_m"]  # a change to one empty cloud reaches no other
    e1.attrs["mine"] = True
    fresh = empty_cloud()
    assert list(e2.columns) == list(fresh.columns) == POINT_CLOUD_COLUMNS and not fresh.attrs
    # Frames share no mutable state: a name given to one frame's column labels stays there.
    for one, make in ((got, lambda: point_cloud(cfg, proc, rng_pos, vel, az, el, snr, bins)),
                      (e1, empty_cloud)):
        one.columns.name = "mine"
        assert make().columns.name is None


def test_estimate_angles_at_the_zenith_with_a_boresight_beam_is_finite():
    """A raised row 180 deg out of phase with the horizontal one (wz = pi on the half-wave
    EVM row: sin(el) = 1, cos(el) = 0) and an exactly boresight beam (wx = 0): 0 / 0 for
    sin(az), reported as azimuth 0 (it is undefined there), not NaN; a beam off boresight at
    the same elevation still clips to +/-90 deg."""
    h_idx, h_pos = np.arange(4), np.arange(4.0)
    v_idx, v_pos = np.arange(4, 6), np.array([1.0, 2.0])
    virt = np.ones((2, 6), np.complex64)
    virt[:, v_idx] = -1.0
    az, el = estimate_angles(virt, np.array([0.0, 1e-9]), h_idx, h_pos, v_idx, v_pos, 0.5)
    np.testing.assert_allclose(np.degrees(el), 90.0)
    assert np.degrees(az[0]) == 0.0 and np.degrees(az[1]) == pytest.approx(90.0)
