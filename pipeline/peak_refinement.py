"""Peak refinement: the maximum of a windowed spectrum between its bins, from a few bins.

A detection's range and Doppler lie between FFT bins. A 3-point interpolator on the power
(the log-parabola of [TI-DDMA] table 14, with its window bias table) throws away the phase and
every bin but three, and lands 1.5 times the Cramer-Rao bound at the detection SNR for a Hann
window. The maximum of the windowed spectrum itself, evaluated between the bins, is the
windowed maximum-likelihood estimate: unbiased for any symmetric window, 1.25 times the bound
for Hann at any SNR above the threshold region.

Between the bins the spectrum is the DTFT of the same N samples, and that is the bins'
Dirichlet interpolation: X(k + delta) = sum_m X[k + m] D(delta - m), D the N-point Dirichlet
kernel. A tapered window's leakage falls fast (Hann: 18 dB per octave), so eleven bins
(m = -5..5) reproduce it: the truncation moves a Hann peak by at most 5e-4 bin (seven bins:
2e-3), 4 % of the bound at 30 dB. Near the ends of a non-cyclic axis (range) the bins past the
end are left out, down to two on each side. Channels (Rx, Tx, slots) carry the same tone
with their own phases: they are combined coherently with the peak bin's channel vector as
weights (`combine_channels`), so the bins' noise projected on the signal only scales the whole
interpolated spectrum and does not move its maximum. A few Newton steps on |X(k + delta)|^2
from the 3-point estimate converge to the maximum; the kernel's first and second derivatives
are analytic (`dirichlet`), so a step costs one pass over the eleven bins.

References
----------
.. [1] [Kay1993] S. M. Kay, Fundamentals of Statistical Signal Processing: Estimation Theory,
       1993, sections 3.11 and 7.10 (the CRB of a sinusoid's frequency; the periodogram
       maximum as its maximum-likelihood estimate).
.. [2] [Rife1974] D. C. Rife and R. R. Boorstyn, "Single-tone parameter estimation from
       discrete-time observations", IEEE Trans. Information Theory 20(5), 1974.
.. [3] [Harris1978] F. J. Harris, "On the use of windows for harmonic analysis with the
       discrete Fourier transform", Proc. IEEE 66(1), 1978 (Hann leakage roll-off).
"""
from __future__ import annotations

import numba
import numpy as np

__all__ = ["HALF_WIDTH", "MIN_HALF_WIDTH", "combine_channels", "dirichlet", "refine_offset",
           "refine_peaks_2d", "neighbour_bins", "peak_patches"]

#: Bins on each side of the peak used to interpolate the spectrum between bins.
HALF_WIDTH = 5
#: Fewest bins on each side for a peak to be refined (near a non-cyclic axis' ends).
MIN_HALF_WIDTH = 2
#: Newton steps (each doubles the accurate digits once started from the 3-point estimate).
_STEPS = 3
#: Below this distance from a bin (bins) the kernel and its derivatives are their Taylor
#: series (the closed forms lose ~eps / y^2 of their value to cancellation there).
_NEAR = 1e-4
#: A refined peak farther than this from its bin (bins) belongs to another bin: keep the start.
_MAX_OFFSET = 0.75


def neighbour_bins(k: np.ndarray, n_bins: int, cyclic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Bins k - HALF_WIDTH .. k + HALF_WIDTH of each peak.

    Parameters
    ----------
    k : (n,) int
        Peak bins.
    n_bins : int
        Bins on the axis.
    cyclic : bool
        Wrap around (Doppler) or not (range).

    Returns
    -------
    idx : (n, 2 HALF_WIDTH + 1) int
        The bins (wrapped, or clipped into the axis).
    on_axis : (n, 2 HALF_WIDTH + 1) bool
        Whether each bin lies on the axis (always True when cyclic); `combine_channels` leaves
        the others out.

    Examples
    --------
    >>> idx, on = neighbour_bins(np.array([1]), 192, cyclic=False)
    >>> idx[0, :6].tolist(), on[0, :6].tolist()
    ([0, 0, 0, 0, 0, 1], [False, False, False, False, True, True])
    """
    m = np.arange(-HALF_WIDTH, HALF_WIDTH + 1)
    idx = np.asarray(k)[:, None] + m
    if cyclic:
        return idx % n_bins, np.ones(idx.shape, dtype=bool)
    return np.clip(idx, 0, n_bins - 1), (idx >= 0) & (idx < n_bins)


def peak_patches(spec: np.ndarray, chirps: np.ndarray, bins: np.ndarray) -> np.ndarray:
    """The patches `refine_peaks_2d` reads, gathered from a cube with Doppler first: each
    peak's channels (transmitter t's Doppler rows, every Rx) at its neighbour range bins.

    Parameters
    ----------
    spec : (n_chirps, n_rx, n_range) complex64, C-contiguous
        Doppler spectra (DDMA: over all chirps, `DdmaMaps.spec`).
    chirps : (n, T, Md) int
        Row of `spec` (Doppler bin) of each peak's Doppler neighbour m for its transmitter t
        (`neighbour_bins`, shifted to the transmitter's sub-band).
    bins : (n, Mr) int
        Each peak's neighbour range bins (`neighbour_bins`).

    Returns
    -------
    (n, T x n_rx, Mr, Md) complex64
        ``patch[p, t n_rx + rx, j, m] = spec[chirps[p, t, m], rx, bins[p, j]]``, C-contiguous.

    Notes
    -----
    One compiled pass over the peaks' samples: numpy's `take` of the same samples needs an
    (n, T, n_rx, Mr, Md) int64 index array built first (R79 DDMA frame, 66 peaks: the patches
    0.47 -> 0.27 ms).
    """
    n, n_t, n_md = chirps.shape
    out = np.empty((n, n_t * spec.shape[1], bins.shape[1], n_md), np.complex64)
    _gather_patches(spec, np.ascontiguousarray(chirps, dtype=np.int64),
                    np.ascontiguousarray(bins, dtype=np.int64), out)
    return out


@numba.njit(cache=True, nogil=True)
def _gather_patches(spec, chirps, bins, out):
    """`peak_patches` into out (n, T x n_rx, Mr, Md)."""
    n, n_t, n_md = chirps.shape
    n_rx = spec.shape[1]
    n_mr = bins.shape[1]
    for p in range(n):
        for t in range(n_t):
            for m in range(n_md):
                c = chirps[p, t, m]
                for rx in range(n_rx):
                    for j in range(n_mr):
                        out[p, t * n_rx + rx, j, m] = spec[c, rx, bins[p, j]]


def combine_channels(x: np.ndarray, on_axis: np.ndarray | None = None) -> np.ndarray:
    """Coherent channel sum with the peak bin's channel vector as weights.

    Parameters
    ----------
    x : (n, C, 2 HALF_WIDTH + 1) complex
        Each peak's C channels at its neighbour bins (`neighbour_bins`).
    on_axis : (n, 2 HALF_WIDTH + 1) bool, optional
        Bins that exist (`neighbour_bins`); the others are set to zero.

    Returns
    -------
    (n, 2 HALF_WIDTH + 1) complex128
        sum_c conj(x[:, c, HALF_WIDTH]) x[:, c, m].
    """
    x = np.asarray(x)
    w = np.conj(x[:, :, HALF_WIDTH]).astype(np.complex128)
    b = np.einsum("nc,ncm->nm", w, x.astype(np.complex128))
    return b if on_axis is None else np.where(on_axis, b, 0.0)


@numba.njit(cache=True, nogil=True)
def dirichlet(y: float, n_fft: int) -> tuple[float, float, float]:
    """The N-point Dirichlet kernel and its first two derivatives at y bins.

    With a = pi, b = pi / N (N = `n_fft`)::

        D(y)   = sin(a y) / (N sin(b y))
        D'(y)  = (a cos(a y) sin(b y) - b sin(a y) cos(b y)) / (N sin(b y)^2)
        D''(y) = (b^2 - a^2) D(y) - 2 b cot(b y) D'(y)

    (D'' from differentiating D' once: the numerator's derivative is (b^2 - a^2) sin(a y)
    sin(b y)). Within `_NEAR` of y = 0 the Taylor series D = 1 - (a^2 - b^2) y^2 / 6,
    D' = -(a^2 - b^2) y / 3, D'' = -(a^2 - b^2) / 3. Valid for |y| < N.

    Examples
    --------
    >>> [round(v, 4) for v in dirichlet(0.0, 64)]
    [1.0, -0.0, -3.2891]
    >>> [round(v, 4) for v in dirichlet(0.5, 64)]
    [0.6367, -1.2731, -1.1909]
    """
    if abs(y) < _NEAR:
        return _taylor(y, n_fft)
    a, b = np.pi, np.pi / n_fft
    return _closed_form(np.sin(a * y), np.cos(a * y), np.sin(b * y), np.cos(b * y), n_fft)


@numba.njit(cache=True, nogil=True)
def _taylor(y: float, n_fft: int) -> tuple[float, float, float]:
    b = np.pi / n_fft
    c = (np.pi * np.pi - b * b) / 3.0
    return 1.0 - 0.5 * c * y * y, -c * y, -c


@numba.njit(cache=True, nogil=True)
def _closed_form(sa: float, ca: float, sb: float, cb: float,
                 n_fft: int) -> tuple[float, float, float]:
    """`dirichlet` from sin and cos of a y and of b y."""
    a, b = np.pi, np.pi / n_fft
    d = sa / (n_fft * sb)
    d1 = (a * ca * sb - b * sa * cb) / (n_fft * sb * sb)
    return d, d1, (b * b - a * a) * d - 2.0 * b * cb / sb * d1


@numba.njit(cache=True, nogil=True)
def _bin_terms(n_fft: int) -> tuple[np.ndarray, np.ndarray]:
    """Per neighbour bin m = -HALF_WIDTH..HALF_WIDTH of an N-point axis: (sin(b m), cos(b m))
    (2, M) with b = pi / N, and the phase exp(j pi m (N - 1) / N) (M,) that turns
    D(delta - m) into the weight of bin k + m in the spectrum at k + delta (numpy's DFT sign;
    the phase exp(-j pi delta (N - 1) / N) common to every channel and bin is left out)."""
    m = np.arange(-HALF_WIDTH, HALF_WIDTH + 1).astype(np.float64)
    shift = np.empty((2, m.size))
    shift[0] = np.sin(np.pi * m / n_fft)
    shift[1] = np.cos(np.pi * m / n_fft)
    return shift, np.exp(1j * np.pi * m * (n_fft - 1) / n_fft)


@numba.njit(cache=True, nogil=True)
def _kernel_at(delta: float, n_fft: int, shift: np.ndarray, phase: np.ndarray,
               out: np.ndarray) -> None:
    """out (3, M) complex128 <- D(delta - m), D'(delta - m), D''(delta - m) times the phase
    of bin m (`_bin_terms`), from four sines and cosines of delta: sin(a (delta - m)) =
    (-1)^m sin(a delta) and sin(b (delta - m)), cos(b (delta - m)) by the angle-difference
    formulas with `shift`."""
    sa, ca = np.sin(np.pi * delta), np.cos(np.pi * delta)
    sbd, cbd = np.sin(np.pi * delta / n_fft), np.cos(np.pi * delta / n_fft)
    for i in range(phase.size):
        m = i - HALF_WIDTH
        y = delta - m
        if abs(y) < _NEAR:
            k0, k1, k2 = _taylor(y, n_fft)
        else:
            sign = -1.0 if abs(m) % 2 else 1.0
            k0, k1, k2 = _closed_form(sign * sa, sign * ca,
                                      sbd * shift[1, i] - cbd * shift[0, i],
                                      cbd * shift[1, i] + sbd * shift[0, i], n_fft)
        out[0, i] = k0 * phase[i]
        out[1, i] = k1 * phase[i]
        out[2, i] = k2 * phase[i]


@numba.njit(cache=True, nogil=True)
def _newton(b: np.ndarray, start: float, n_fft: int, shift: np.ndarray, phase: np.ndarray,
            work: np.ndarray) -> float:
    """`refine_offset` of one peak: Newton steps on P(delta) = |X(delta)|^2 with
    X = sum_m b_m D(delta - m) e^{j pi m (N-1)/N} and its analytic derivatives,
    P' = 2 Re(conj(X) X'), P'' = 2 (|X'|^2 + Re(conj(X) X'')). `work`: (3, M) scratch."""
    ok = True
    for i in range(HALF_WIDTH - MIN_HALF_WIDTH, HALF_WIDTH + MIN_HALF_WIDTH + 1):
        ok = ok and b[i] != 0
    d = start
    for _ in range(_STEPS):
        _kernel_at(d, n_fft, shift, phase, work)
        x0 = x1 = x2 = 0j
        for i in range(b.size):
            x0 += b[i] * work[0, i]
            x1 += b[i] * work[1, i]
            x2 += b[i] * work[2, i]
        p1 = 2.0 * (x0.conjugate() * x1).real
        p2 = 2.0 * (abs(x1) ** 2 + (x0.conjugate() * x2).real)
        ok = ok and p2 < 0  # a maximum, not a minimum or an inflection
        if ok:
            d += min(max(-p1 / p2, -0.5), 0.5)
    return d if ok and abs(d) <= _MAX_OFFSET else start


@numba.njit(cache=True, nogil=True)
def _newton_rows(b: np.ndarray, start: np.ndarray, n_fft: int) -> np.ndarray:
    shift, phase = _bin_terms(n_fft)
    work = np.empty((3, phase.size), np.complex128)
    out = np.empty(start.size)
    for p in range(start.size):
        out[p] = _newton(b[p], start[p], n_fft, shift, phase, work)
    return out


def refine_offset(b: np.ndarray, start: np.ndarray, n_fft: int) -> np.ndarray:
    """Offset of the maximum of the interpolated spectrum from the peak bin, bins.

    Parameters
    ----------
    b : (n, 2 HALF_WIDTH + 1) complex
        The (channel-combined, `combine_channels`) spectrum at bins k - HALF_WIDTH .. k +
        HALF_WIDTH of each peak, windowed N-point DFT values (numpy's sign convention).
    start : (n,) float
        First guess of each offset, bins (a 3-point interpolator's).
    n_fft : int
        N, the DFT length the bins come from (no zero padding).

    Returns
    -------
    (n,) float64
        Offset of the maximum, bins; `start` where the Newton steps do not converge on a
        maximum within 0.75 bin (a neighbour's peak, or noise), or where fewer than
        `MIN_HALF_WIDTH` bins on either side are on the axis (zeros in `b`).

    Examples
    --------
    >>> import numpy as np
    >>> n = 256
    >>> w = np.hanning(n + 1)[:-1]
    >>> x = w * np.exp(2j * np.pi * (40.3 * np.arange(n) / n))
    >>> X = np.fft.fft(x)
    >>> b = X[35:46][None]   # bins 40 - 5 .. 40 + 5
    >>> round(float(refine_offset(b, np.array([0.25]), n)[0]), 3)
    0.3
    """
    return _newton_rows(np.ascontiguousarray(b, dtype=np.complex128),
                        np.ascontiguousarray(start, dtype=np.float64), int(n_fft))


def refine_peaks_2d(patch: np.ndarray, on_axis: np.ndarray, start_r: np.ndarray,
                    start_d: np.ndarray, n_fft_r: int, n_fft_d: int, passes: int = 2
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Range and Doppler offsets of the maximum of each peak's windowed range-Doppler
    spectrum, over its channels.

    Alternating: the channels are interpolated to the current Doppler offset and the range
    offset refined on them (`refine_offset`), then the same for Doppler at the new range
    offset. Each axis is estimated on the spectrum at the other's maximum, not at its nearest
    bin, so the other axis' scalloping (up to 1.4 dB for Hann) costs no SNR. The channel
    weights are the channel vector at the current maximum (`combine_channels` takes the bin's).

    Parameters
    ----------
    patch : (n, C, 2 HALF_WIDTH + 1, 2 HALF_WIDTH + 1) complex
        Each peak's channels at range bins r - HALF_WIDTH .. r + HALF_WIDTH (axis 2) and
        Doppler bins d - HALF_WIDTH .. d + HALF_WIDTH (axis 3).
    on_axis : (n, 2 HALF_WIDTH + 1) bool
        Range bins that exist (`neighbour_bins`); Doppler is cyclic.
    start_r, start_d : (n,) float
        First guesses (3-point estimates), bins from r and d.
    n_fft_r, n_fft_d : int
        DFT lengths of the two axes.
    passes : int
        Alternations.

    Returns
    -------
    off_r, off_d : (n,) float64
        Offsets from r and d, bins (`refine_offset`'s fall-backs apply per axis).
    """
    off_r = np.array(start_r, dtype=np.float64)
    off_d = np.array(start_d, dtype=np.float64)
    _alternate(np.ascontiguousarray(patch, dtype=np.complex64), np.ascontiguousarray(on_axis),
               off_r, off_d, int(n_fft_r), int(n_fft_d), int(passes))
    return off_r, off_d


@numba.njit(cache=True, nogil=True)
def _alternate(x: np.ndarray, on_axis: np.ndarray, off_r: np.ndarray, off_d: np.ndarray,
               n_fft_r: int, n_fft_d: int, passes: int) -> None:
    """`refine_peaks_2d` on x (n, C, Mr, Md) complex64, updating off_r and off_d (n,) in
    place; range bins off the axis (on_axis (n, Mr) False) count as zeros. Per peak and
    axis: y_c = the channels interpolated to the other axis' offset (`_interpolate` with
    `_kernel_at`'s weights), w_c = y_c at the own axis' offset, b = sum_c conj(w_c) y_c
    (`combine_channels` at the current maximum), then `_newton` on b."""
    n, c, m_r, m_d = x.shape
    shift_r, phase_r = _bin_terms(n_fft_r)
    shift_d, phase_d = _bin_terms(n_fft_d)
    k_r = np.empty((3, m_r), np.complex128)
    k_d = np.empty((3, m_d), np.complex128)
    # The contractions over the other axis in the data's precision (half the time of mixed
    # complex64 x complex128 products); the combined spectra and the Newton steps in float64.
    w = np.empty(max(m_r, m_d), np.complex64)
    y_r = np.empty((c, m_r), np.complex64)
    y_d = np.empty((c, m_d), np.complex64)
    for p in range(n):
        for _ in range(passes):
            _kernel_at(off_d[p], n_fft_d, shift_d, phase_d, k_d)
            _kernel_at(off_r[p], n_fft_r, shift_r, phase_r, k_r)
            w[:m_d] = k_d[0]
            # x[p, :, :, :] is typed as a strided view, like the transposed one below: one
            # compiled `_interpolate` serves both calls (x[p] would add a contiguous variant).
            _interpolate(x[p, :, :, :], w[:m_d], y_r)
            for i in range(m_r):
                if not on_axis[p, i]:
                    y_r[:, i] = 0
            off_r[p] = _newton(_combine(y_r, k_r[0]), off_r[p], n_fft_r, shift_r, phase_r, k_r)
            _kernel_at(off_r[p], n_fft_r, shift_r, phase_r, k_r)
            for i in range(m_r):
                w[i] = k_r[0, i] if on_axis[p, i] else 0
            _interpolate(x[p].transpose(0, 2, 1), w[:m_r], y_d)
            off_d[p] = _newton(_combine(y_d, k_d[0]), off_d[p], n_fft_d, shift_d, phase_d, k_d)


@numba.njit(cache=True, nogil=True)
def _interpolate(x: np.ndarray, w: np.ndarray, y: np.ndarray) -> None:
    """y (C, M) <- sum_j x[c, m, j] w[j]: channels x (C, M, M_other) complex64 interpolated
    along their last axis with the weights w (M_other,), in complex64."""
    c, m, m_other = x.shape
    for ch in range(c):
        for i in range(m):
            acc = np.complex64(0)
            for j in range(m_other):
                acc += x[ch, i, j] * w[j]
            y[ch, i] = acc


@numba.njit(cache=True, nogil=True)
def _combine(y: np.ndarray, w: np.ndarray) -> np.ndarray:
    """y (C, M) channels along one axis -> (M,): sum_c conj(v_c) y_c with v_c = sum_m
    y_c[m] w[m], the channel vector at the offset the weights w interpolate to."""
    c, m = y.shape
    b = np.zeros(m, np.complex128)
    for ch in range(c):
        v = 0j
        for i in range(m):
            v += np.complex128(y[ch, i]) * w[i]
        v = v.conjugate()
        for i in range(m):
            b[i] += v * np.complex128(y[ch, i])
    return b
