"""TI's DC range-signature calibration (`pipeline.dc_range_signature`): the first numAvg loops
measured and left alone, every later chirp's near-DC bins minus its Tx slot's mean."""
import numpy as np
import pytest

import pipeline
from pipeline.dc_range_signature import DcRangeSignature, DcSignatureCalibrator, signature_bins


def test_bins_are_ti_order_positive_then_negative():
    np.testing.assert_array_equal(signature_bins(-5, 8, 128),
                                  list(range(9)) + [123, 124, 125, 126, 127])
    np.testing.assert_array_equal(signature_bins(0, 0, 64), [0])


def _frames(rng, n_frames, loops=8, slots=3, rx=4, bins=32):
    """Range-FFT frames: a per-(slot, Rx, bin) constant coupling signature on every bin plus
    unit complex noise."""
    sig = rng.normal(size=(slots, rx, bins)) + 1j * rng.normal(size=(slots, rx, bins))
    sig *= 50.0
    noise = (rng.normal(size=(n_frames, loops, slots, rx, bins))
             + 1j * rng.normal(size=(n_frames, loops, slots, rx, bins))) / np.sqrt(2)
    x = (sig[None, None] + noise).astype(np.complex64)
    return sig, x.reshape(n_frames, loops * slots, rx, bins)


def test_calibrates_over_num_avg_loops_then_subtracts_each_slots_mean():
    """numAvg = 16 loops over 8-loop frames: frames 0 and 1 measure (not compensated), frame
    2 on: the signature bins carry only noise (the mean of 16 noise samples is left:
    |residual| ~ 1/4), the other bins keep the coupling untouched."""
    rng = np.random.default_rng(1)
    sig, frames = _frames(rng, 4)
    cal = DcSignatureCalibrator(-3, 4, 16, 3)
    got = [cal.process(f) for f in frames[:2]]
    assert got == [None, None] and cal.signature is not None
    bins = signature_bins(-3, 4, 32)
    np.testing.assert_allclose(cal.signature.mean, sig[..., bins], atol=1.5)
    out = cal.process(frames[2]).subtract(frames[2])
    loops = out.reshape(8, 3, 4, 32)
    assert np.abs(loops[..., bins]).mean() < 1.5  # noise only (mean |n| = 0.89, +1/4)
    other = np.setdiff1d(np.arange(32), bins)
    np.testing.assert_array_equal(out[..., other], frames[2][..., other])
    assert not np.shares_memory(out, frames[2])


def test_frame_that_completes_the_calibration_is_compensated_after_it():
    """numAvg = 4 loops of an 8-loop frame: loops 0-3 measured as they are, loops 4-7 of the
    same frame compensated (TI subtracts from the chirp after the count is reached)."""
    rng = np.random.default_rng(2)
    _, frames = _frames(rng, 1)
    sig = DcSignatureCalibrator(0, 2, 4, 3).process(frames[0])
    assert sig.first_loop == 4
    out = sig.subtract(frames[0]).reshape(8, 3, 4, 32)
    ref = frames[0].reshape(8, 3, 4, 32)
    np.testing.assert_array_equal(out[:4], ref[:4])
    assert np.abs(out[4:, ..., :3]).mean() < 1.5 < np.abs(ref[4:, ..., :3]).mean()


def test_processing_config_takes_only_a_signature():
    with pytest.raises(ValueError, match="dc_range_signature must be a DcRangeSignature or "
                                         "None, got str"):
        pipeline.ProcessingConfig().replace(dc_range_signature="x")


def test_signature_that_does_not_fit_the_frame_is_refused():
    sig = DcRangeSignature(signature_bins(0, 2, 16), np.zeros((2, 4, 3), np.complex64))
    with pytest.raises(ValueError, match=r"a \(9, 4, 16\) range-FFT frame does not fit a DC "
                                         r"range signature of 2 slots x 4 Rx"):
        sig.subtract(np.zeros((9, 4, 16), np.complex64))
