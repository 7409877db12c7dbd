"""Shifter sweep file, report metrics and the `radar-harness shifter` command."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import radarsim
from harness.cell.config import radar_config
from harness.cell.spec import known_schemes
from harness.cli import main
from harness.report.shifter import _psl_db, shifter_table
from harness.sweep.file import load_sweep
from radarsim.calibration import shifter_phase_residual_deg
from radarsim.radar_config import radar_fields

SWEEP = Path(__file__).resolve().parents[2] / "harness" / "sweeps" / "shifter.toml"


def test_psl_of_uniform_array_is_the_dirichlet_sidelobe():
    """Unwindowed N = 12 uniform array sampled on a fine cyclic grid: the peak sidelobe is the
    first maximum of the Dirichlet kernel sin(N x / 2) / (N sin(x / 2)) between its first and
    second nulls (-13.06 dB for N = 12; -13.26 dB only as N -> infinity, Harris 1978)."""
    from scipy.optimize import minimize_scalar
    n = 12
    dirichlet = lambda x: -abs(np.sin(n * x / 2) / (n * np.sin(x / 2)))  # noqa: E731
    peak = -minimize_scalar(dirichlet, bounds=(2 * np.pi / n, 4 * np.pi / n),
                            method="bounded", options={"xatol": 1e-10}).fun
    k = np.arange(n * 400)
    af = np.abs(np.exp(-2j * np.pi * np.outer(np.arange(n), k) / k.size).sum(axis=0)) ** 2
    assert _psl_db(10 * np.log10(af)) == pytest.approx(20 * np.log10(peak), abs=0.01)
    assert 20 * np.log10(peak) == pytest.approx(-13.06, abs=0.01)


def test_shifter_sweep_file_covers_errors_calibration_and_all_schemes():
    spec = load_sweep(SWEEP)
    assert spec.schemes == tuple(known_schemes())
    names = [v.name for v in spec.variants]
    assert len(names) == 10
    fields = {v.name: radar_fields(v.radar) for v in spec.variants}  # the file's parts, by field
    rms = sorted({f["shifter_phase_error_deg"]["rms"] for f in fields.values()})
    assert rms == [0.0, 2.0, 5.0, 10.0, 20.0]
    assert sum("shifter_calibration_deg" in f for f in fields.values()) == 5
    worst = [v for v in spec.variants if v.name.startswith("shifter_20deg")]
    for name in radarsim.MIMO_SCHEMES:
        r = {v.name.endswith("_cal"): shifter_phase_residual_deg(radar_config(v.radar, name))
             for v in worst}
        assert np.nanmax(np.abs(r[True])) <= np.nanmax(np.abs(r[False]))


def test_shifter_table_reads_the_metrics_columns(tmp_path):
    """Failures and azimuth RMSE come from the summary (metrics.velocity, metrics.detection),
    pooled over cells: failures per frame, RMSE weighted by the error samples."""
    import json
    rows = [{"scenario": sc, "variant": "v", "seed": 0, "scheme": "ddma", "n_frames": 10,
             "n_ghost": g, "n_detections": 100, "n_velocity_resolution_failures": f,
             "azimuth_error_rmse_deg": az, "n_error_samples": n, "error": ""}
            for sc, g, f, az, n in (("a", 5, 3, 1.0, 10), ("b", 15, 1, 2.0, 30))]
    pd.DataFrame(rows).to_parquet(tmp_path / "summary.parquet", index=False)
    (tmp_path / "manifest.json").write_text(json.dumps({"sweep": {"variants": [
        {"name": "v", "radar": {"shifter_phase_error_deg": {"rms": 5.0}}}]}}))
    t = shifter_table(tmp_path, probe=False).iloc[0]
    assert t["ghost_rate"] == pytest.approx(0.1)
    assert t["velocity_resolution_failures_per_frame"] == pytest.approx(4 / 20)
    assert t["azimuth_rmse_deg"] == pytest.approx(np.sqrt((10 * 1 + 30 * 4) / 40))


def test_cli_shifter_prints_lines(capsys):
    assert main(["shifter", "--n-chirps", "256", "--quadrature-skew-deg", "20"]) == 0
    out = capsys.readouterr().out
    assert out.count("mirror ghost") == 2 and "after calibration" in out


@pytest.mark.parametrize("args, message", [
    (["--step-deg", "70"], "--step-deg 70.0: 360 / step_deg must be an integer >= 2"),
    (["--step-deg", "nan"], "argument --step-deg: nan is outside (0, 180] deg"),
    (["--tx", "5"], "argument --tx: 5 is outside 1..4"),
    (["--n-chirps", "101"], "--n-chirps 101 must be a positive multiple of the code period 4"),
    (["--n-chirps", "1000000000000"], "argument --n-chirps: 1000000000000 is outside 2..16384"),
    (["--n-chirps", "1e12"], "argument --n-chirps: '1e12' is not an integer"),
    (["--error-deg-rms", "-1"], "argument --error-deg-rms: -1 is outside [0, 30] deg"),
    (["--error-deg-rms", "1e9"], "argument --error-deg-rms: 1e9 is outside [0, 30] deg"),
    (["--gain-error-db-rms", "-1"], "argument --gain-error-db-rms: -1 is outside [0, 6] dB"),
    (["--seed", "-1"], "argument --seed: -1 is outside 0..4294967295"),
    (["--range-m", "0"], "argument --range-m: 0 is outside (0, 250] m"),
    (["--range-m", "200"], "--range-m 200 m, rcs_m2=10"),
    (["--quadrature-skew-deg", "nan"], "argument --quadrature-skew-deg: nan is outside"),
    (["--quadrature-skew-deg", "1e9"], "argument --quadrature-skew-deg: 1e9 is outside"),
    (["--distribution", "nope"], "invalid choice: 'nope'"),
])
def test_cli_shifter_bad_input_exits_2(capsys, args, message):
    assert main(["shifter", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err


def test_cli_shifter_refuses_calibrating_on_noise(capsys):
    """A reflector far beyond the calibration's SNR was measured on noise and used."""
    assert main(["shifter", "--range-m", "200", "--n-chirps", "64"]) == 2
    err = capsys.readouterr().err
    assert "measurement SNR -15.1 dB per chirp" in err and "below the 23.2 dB" in err


def test_cli_shifter_plot_folder_checked_before_the_experiment(tmp_path, capsys, monkeypatch):
    import harness.shifter_experiment as se
    monkeypatch.setattr(se, "phase_step_experiment", lambda *a, **k: pytest.fail("ran"))
    assert main(["shifter", "--plot", str(tmp_path / "no" / "x.png")]) == 2
    assert "--plot" in capsys.readouterr().err
