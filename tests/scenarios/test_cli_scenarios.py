"""`radar-harness scenarios` and `radar-harness show` (bird's-eye PNG and GIF)."""
from __future__ import annotations

import functools

import pytest
from PIL import Image

import scenarios.plot
from harness.cli import main
from scenarios import SCENARIOS, run_scenario
from scenarios.plot import box_corners, plot_birdseye


def test_scenarios_lists_one_case_per_line(capsys):
    assert main(["scenarios"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == len(SCENARIOS)
    assert [ln.split()[0] for ln in lines] == list(SCENARIOS)


def test_show_writes_png_and_gif(tmp_path, capsys, monkeypatch):
    # The GIF with 8 of its (default 40) evenly spaced frames: the same drawing and writing
    # code, a fifth of the time (each frame is a full matplotlib redraw, ~0.1 s).
    monkeypatch.setattr(scenarios.plot, "animate_birdseye",
                        functools.partial(scenarios.plot.animate_birdseye, max_frames=8))
    assert main(["show", "r79_critical_distance_60", "--out", str(tmp_path)]) == 0
    png = tmp_path / "r79_critical_distance_60.png"
    gif = tmp_path / "r79_critical_distance_60.gif"
    assert png.stat().st_size > 5000 and gif.stat().st_size > 5000
    with Image.open(gif) as im:
        assert im.n_frames == 8  # every frame drawn is written (the case has 60 > 8)
    with Image.open(png) as im:
        # Not blank: many distinct colours (FOV wedge, boxes, rails, text).
        assert len(im.convert("RGB").getcolors(maxcolors=1 << 16) or []) > 20
    assert "wrote" in capsys.readouterr().out


def test_show_default_is_current_directory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run = run_scenario("zero_relative_follower", duration_s=0.2)
    plot_birdseye(run, "x.png")
    assert (tmp_path / "x.png").exists()


def test_show_unknown_case_exit_2(capsys, tmp_path):
    assert main(["show", "no_such_case", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "no_such_case" in err and "r79_motorcycle_rear" in err


def test_box_corners_yawed():
    c = box_corners(0.0, 0.0, 90.0, 4.0, 2.0)[0]
    assert abs(c[:, 1]).max() == pytest.approx(2.0)
    assert abs(c[:, 0]).max() == pytest.approx(1.0)
