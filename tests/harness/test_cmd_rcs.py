"""`radar-harness rcs`: prints the model pattern against the references, plots, bad input."""
from __future__ import annotations

import pytest

from harness.cli import main


def test_rcs_prints_model_and_reference(capsys, tmp_path):
    out = tmp_path / "car.png"
    assert main(["rcs", "car", "--draws", "2", "--plot", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "TR 38.901 Table 7.9.2.1-4" in text
    row90 = next(line for line in text.splitlines() if line.split()[:1] == ["90"])
    model, ref = float(row90.split()[1]), float(row90.split()[-1])
    assert ref == pytest.approx(20.1, abs=0.05)
    assert model == pytest.approx(ref, abs=6.0)   # 2 draws of a 3.41 dB log-normal
    assert out.stat().st_size > 10_000


def test_rcs_class_without_source_says_so(capsys):
    assert main(["rcs", "truck", "--draws", "1"]) == 0
    assert "no published pattern could be sourced" in capsys.readouterr().out


def test_rcs_bicycle_lists_both_sources(capsys):
    """The cyclist's pattern (rider + bicycle) and the bicycle's own sector means."""
    assert main(["rcs", "bicycle", "--draws", "1"]) == 0
    text = capsys.readouterr().out
    assert "Belgiovane" in text and "TR 38.901" in text
    row90 = next(line for line in text.splitlines() if line.split()[:1] == ["90"])
    assert [float(v) for v in row90.split()[-2:]] == pytest.approx([0.7, -8.1], abs=0.05)


@pytest.mark.parametrize("argv, match", [
    (["rcs", "tank"], "CLASS='tank' unknown"),
    (["rcs", "car", "--range-m", "0"], "--range-m"),
    (["rcs", "car", "--draws", "0"], "--draws"),
])
def test_rcs_bad_input_exits_2(argv, match, capsys):
    assert main(argv) == 2
    assert match in capsys.readouterr().err
