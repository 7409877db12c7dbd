"""tests.numba_warm: the signature list it reads."""
import pytest

from tests import numba_warm


def test_signature_list_lines_are_module_function_signature(tmp_path):
    p = tmp_path / "sigs.txt"
    p.write_text("# comment\npipeline.cfar _os_peaks (array(float32, 3d, C), float64)\n\n")
    assert numba_warm.read_signatures(p) == {
        "pipeline.cfar": [("_os_peaks", "(array(float32, 3d, C), float64)")]}
    p.write_text("pipeline.cfar _os_peaks\n")
    with pytest.raises(ValueError, match=r"sigs.txt:1: 'pipeline.cfar _os_peaks' is not"):
        numba_warm.read_signatures(p)
