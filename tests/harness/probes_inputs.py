"""The probe set, inputs: sweep files and keys, the shifter command, chip and board configs,
ADC frames and interference equipment (`tests.harness.probe_kit`)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from tests.harness.probe_kit import Probe, directory, readonly_dir, ti_reader, vary, write_file


def sweep_probes() -> list[Probe]:
    head = 'name = "p"\nscenarios = ["head_on_aliasing"]\nduration_s = 0.2\n'
    big_vary = head + vary({"processing.cfar_threshold_db": 100,
                             "radar.phase_noise_deg_rms": 100, "radar.tx_power_dbm": 100})
    huge_vary = head + vary({"processing.cfar_threshold_db": 1000,
                              "radar.phase_noise_deg_rms": 1000, "radar.tx_power_dbm": 1000,
                              "radar.noise_figure_db": 1000})

    def sweep(text, *extra):
        return lambda t: ["sweep", write_file(t, "s.toml", text), "--out", t / "r", "--workers",
                          "1", *extra]
    return [
        Probe("sweeps", "vary_product_1e6", sweep(big_vary),
              r"1000000 variants .* limit 10000 cells"),
        Probe("sweeps", "vary_product_1e12", sweep(huge_vary),
              r"1000000000000 variants .* limit 10000 cells"),
        Probe("sweeps", "baseline_not_run_file",
              sweep(head + 'schemes = ["ddma", "bpm"]\nbaseline_scheme = "tdma"\n'),
              r"baseline_scheme='tdma' is not among the schemes run \['ddma', 'bpm'\]"),
        Probe("sweeps", "baseline_not_run_cli",
              sweep(head, "--schemes", "ddma", "bpm", "--baseline-scheme", "tdma"),
              r"--baseline-scheme tdma is not among the schemes run \['ddma', 'bpm'\]"),
        Probe("sweeps", "run_baseline_not_run",
              lambda t: ["run", "head_on_aliasing", "--duration-s", "0.2", "--schemes", "ddma",
                         "bpm", "--baseline-scheme", "tdma"],
              r"--baseline-scheme tdma is not among the schemes run"),
        Probe("sweeps", "unknown_scheme",
              lambda t: ["run", "head_on_aliasing", "--schemes", "ddma", "nope"],
              r"unknown scheme\(s\) \['nope'\]"),
        Probe("sweeps", "seed_true", sweep(head + "seeds = [true]\n"), r"seeds=\[True\]"),
        Probe("sweeps", "radar_seed_true_in_table",
              sweep(head + '[base.radar]\nshifter_phase_error_deg = {distribution = "inl_dnl", '
                           'rms = 2.0, seed = true}\n'), r"seed=True"),
        Probe("sweeps", "rms_true",
              sweep(head + '[base.radar]\nshifter_phase_error_deg = {distribution = "inl_dnl", '
                           'rms = true, seed = 0}\n'), r"rms=True"),
        Probe("sweeps", "calibration_on_noise",
              sweep(head + '[base.radar]\nphase_quantization = "round"\n'
                           'shifter_calibration_deg = {seed = 0, range_m = 1e5}\n'),
              r"calibration.*SNR.*-?\d+(\.\d)? dB.*below"),
        Probe("sweeps", "calibration_n_repeats_1e8",
              sweep(head + '[base.radar]\nphase_quantization = "round"\n'
                           'shifter_calibration_deg = {seed = 0, n_repeats = 100000000}\n'),
              r"n_repeats=100000000 .*4096"),
        Probe("sweeps", "radar_tx_channels_float",
              sweep(head + "[base.radar]\ntx_channels = [1.7, 3.9, 2.0, 4.0]\n"),
              r"tx_channels=.*1\.7.*integer"),
        Probe("sweeps", "radar_tx_order_string",
              sweep(head + '[base.radar]\ntx_order = "1342"\n'),
              r"tx_order='1342'.*(tuple|sequence|list)"),
        Probe("sweeps", "duration_nan", sweep(head.replace("0.2", "nan")), r"duration_s=nan"),
        Probe("sweeps", "out_is_a_file",
              lambda t: ["sweep", write_file(t, "s.toml", head), "--out",
                         write_file(t, "f", "x"), "--workers", "1"], r"not a directory"),
        Probe("sweeps", "tls_garbage_certificate",
              lambda t: ["sweep", write_file(t, "s.toml", head), "--out", t / "r", "--scheduler",
                         "tls://127.0.0.1:9", "--scheduler-timeout-s", "2", "--security",
                         _tls_files(t, garbage=True)],
              r"ca_file = 'ca\.pem' is not a PEM CA certificate"),
        Probe("sweeps", "tls_key_mismatch_missing",
              lambda t: ["sweep", write_file(t, "s.toml", head), "--out", t / "r", "--scheduler",
                         "tls://127.0.0.1:9", "--security", _tls_files(t, garbage=False,
                                                                        drop="key")],
              r"missing key\(s\) \['key'\]"),
    ]


def _tls_files(tmp: Path, garbage: bool, drop: str | None = None) -> Path:
    for name in ("ca.pem", "cert.pem", "key.pem"):
        (tmp / name).write_text("this is not a certificate\n" if garbage else "")
    keys = {"ca_file": "ca.pem", "cert": "cert.pem", "key": "key.pem"}
    if drop:
        del keys[drop]
    return write_file(tmp, "sec.toml", "".join(f'{k} = "{v}"\n' for k, v in keys.items()))


def shifter_probes() -> list[Probe]:
    def sh(*a):
        return lambda t: ["shifter", *a]
    return [
        Probe("shifter", "n_chirps_1e12", sh("--n-chirps", "1000000000000"),
              r"--n-chirps.*1000000000000.*\.\.16384"),
        Probe("shifter", "n_chirps_float", sh("--n-chirps", "1e12"), r"--n-chirps"),
        Probe("shifter", "error_rms_huge", sh("--error-deg-rms", "1e9"),
              r"--error-deg-rms.*1e\+?0?9.*outside"),
        Probe("shifter", "gain_rms_negative", sh("--gain-error-db-rms", "-1"),
              r"--gain-error-db-rms.*-1.*outside"),
        Probe("shifter", "skew_huge", sh("--quadrature-skew-deg", "1e9"),
              r"--quadrature-skew-deg.*outside"),
        Probe("shifter", "step_nan", sh("--step-deg", "nan"), r"--step-deg.*nan"),
        Probe("shifter", "step_not_divisor", sh("--step-deg", "7"), r"--step-deg.*7"),
        Probe("shifter", "tx_7", sh("--tx", "7"), r"--tx.*7.*1\.\.4"),
        Probe("shifter", "range_negative", sh("--range-m", "-1"), r"--range-m.*-1.*outside"),
        Probe("shifter", "range_far_noise", sh("--range-m", "200", "--n-chirps", "64"),
              r"calibration.*SNR.*below"),
        Probe("shifter", "seed_negative", sh("--seed", "-1"), r"--seed.*-1"),
        Probe("shifter", "plot_read_only",
              lambda t: (["shifter", "--n-chirps", "64", "--plot", t / "ro" / "x.png"],
                         readonly_dir(t / "ro")), r"--plot.*read-only"),
        Probe("shifter", "plot_is_dir",
              lambda t: ["shifter", "--n-chirps", "64", "--plot", directory(t / "d")],
              r"--plot.*directory"),
        Probe("shifter", "calibrate_n_repeats_1e8", cli=False,
              call=lambda t: _calibrate(n_repeats=100_000_000), match=r"n_repeats=100000000"),
        Probe("shifter", "calibrate_n_repeats_true", cli=False,
              call=lambda t: _calibrate(n_repeats=True), match=r"n_repeats=True"),
        Probe("shifter", "calibrate_far_below_snr", cli=False,
              call=lambda t: _calibrate(range_m=1e5),
              match=r"SNR -\d+\.\d dB .*below the \d+\.\d dB"),
        Probe("shifter", "config_calibration_on_noise", cli=False,
              call=lambda t: _calibration_request({"seed": 0, "range_m": 1e5}),
              match=r"SNR.*below"),
        Probe("shifter", "table_rms_true", cli=False,
              call=lambda t: _radar(shifter_phase_error_deg={"distribution": "inl_dnl",
                                                             "rms": True, "seed": 0}),
              match=r"rms=True"),
        Probe("shifter", "table_seed_true", cli=False,
              call=lambda t: _radar(shifter_phase_error_deg={"distribution": "inl_dnl",
                                                             "rms": 2.0, "seed": True}),
              match=r"seed=True"),
        Probe("shifter", "calibration_seed_true", cli=False,
              call=lambda t: _calibration_request({"seed": True}),
              match=r"seed=True"),
        Probe("shifter", "calibration_request_in_config", cli=False,
              call=lambda t: _radar(phase_quantization="round",
                                    shifter_calibration_deg={"seed": 0}),
              match=r"is a calibration request, not a measured table"),
    ]


def _radar(**kw):
    import radarsim
    return radarsim.RadarConfig.from_fields(**kw)


def _calibration_request(request):
    """A sweep's calibration request, resolved as the harness resolves it (a config itself
    never measures)."""
    import radarsim
    cfg = radarsim.presets.r79_ddma(phase_quantization="round")
    return radarsim.resolve_calibration(cfg, request)


def _calibrate(**kw):
    import radarsim
    cfg = radarsim.presets.r79_ddma(phase_quantization="round")
    return radarsim.calibrate_shifters(cfg, rng=np.random.default_rng(0), **kw)


def config_probes() -> list[Probe]:
    def cfg(name, match, **kw):
        return Probe("chips_boards", name, cli=False, call=lambda t: _radar(**kw), match=match)
    return [
        cfg("tx_channels_float", r"tx_channels=\(1\.7, 3\.9\).*integer", n_tx=2,
            tx_channels=(1.7, 3.9)),
        cfg("tx_order_string", r"tx_order='1342'", tx_order="1342"),
        cfg("rx_channels_float", r"rx_channels=.*2\.5.*integer", rx_channels=(1, 2.5, 3, 4)),
        cfg("tx_order_float", r"tx_order=.*1\.5", tx_order=(1.5, 3, 4, 2)),
        cfg("unknown_chip", r"chip='AWR9999'.*not one of|unknown.*AWR9999", chip="AWR9999"),
        cfg("board_of_other_chip", r"board=.*carries", chip="AWR1843", board="AWR2944EVM"),
        cfg("n_tx_over_chip", r"n_tx=5", n_tx=5),
        cfg("phase_noise_true", r"phase_noise_deg_rms=True", phase_noise_deg_rms=True),
        cfg("adc_mode_unknown", r"adc_mode='complex3x'", adc_mode="complex3x"),
        cfg("unknown_board", r"board='NOPE'", board="NOPE"),
        cfg("n_chirps_huge", r"n_chirps=", n_chirps=10**9),
        cfg("mimo_unknown", r"mimo='fdma'", mimo="fdma"),
    ]


def adc_probes() -> list[Probe]:
    def frame(kind: str):
        import pipeline
        cfg = ti_reader()(Path(__file__).resolve().parents[1] / "radarsim" / "profiles"
                           / "xwr16_lab.cfg").radar
        assert cfg.is_complex
        adc = np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.complex64)
        if kind == "nan":
            adc[:] = np.nan
        elif kind == "one_inf":
            adc[3, 1, 7] = np.inf
        elif kind == "over_full_scale":
            adc[:, :, 5] = 1e9 + 1e9j
            pc = pipeline.process_frame(cfg, adc)
            sat = pc.attrs.get("saturation", {})
            if sat.get("saturated") and (len(pc) == 0 or pc["saturated"].all()):
                raise ValueError("saturated: flagged (the clear answer)")
            return pc
        return pipeline.process_frame(cfg, adc)

    def real(kind):
        import pipeline
        import radarsim
        cfg = radarsim.presets.r79_ddma()
        adc = np.zeros((cfg.n_chirps, cfg.n_rx, cfg.n_samples), np.float32)
        adc[0, 0, 0] = np.nan
        return pipeline.process_frame(cfg, adc if kind == "float" else adc.astype(np.int32))

    return [
        Probe("complex_adc", "complex_nan", cli=False, call=lambda t: frame("nan"),
              match=r"frame .*non-finite.*\b\d+\b"),
        Probe("complex_adc", "complex_one_inf", cli=False, call=lambda t: frame("one_inf"),
              match=r"1 non-finite sample.*chirp 3, Rx 1, sample 7"),
        Probe("complex_adc", "complex_beyond_full_scale", cli=False,
              call=lambda t: frame("over_full_scale"), match=r"saturated: flagged"),
        Probe("complex_adc", "real_float_frame", cli=False, call=lambda t: real("float"),
              match=r"int16"),
        Probe("complex_adc", "real_int32_frame", cli=False, call=lambda t: real("int32"),
              match=r"int16"),
    ]


def interference_probes() -> list[Probe]:
    base = dict(position_m=[[30.0, 0.0, 0.0]], radial_velocity_mps=[0.0], tx_gain_dbi=[10.0],
                start_freq_hz=[77e9], slope_hz_per_s=[20e12], chirp_period_s=[40e-6],
                ramp_time_s=[30e-6], chirp_offset_s=[1e-6], tx_power_dbm=[12.0])

    def itf(**kw):
        import radarsim
        from radarsim.interference import Interferers
        i = Interferers(**{**base, **kw})
        cfg = radarsim.presets.r79_ddma()
        return radarsim.simulate_frame(cfg, radarsim.Scatterers(
            position_m=np.zeros((0, 3)), velocity_mps=np.zeros((0, 3)), rcs_m2=np.zeros(0)),
            rng=np.random.default_rng(0), interferers=i)

    def eq(**kw):
        from scenarios.equipment import RadarEquipment
        return RadarEquipment(**kw)

    case = (Path(__file__).resolve().parents[2] / "scenarios" / "cases"
            / "interference_same_slope_ghosts.toml").read_text()
    assert "chirp_offset_s = 0.3e-6\n" in case and "tx_power_dbm = 12.0\n" in case

    def case_probe(name, old, new, match):
        return Probe("interference", name,
                     lambda t: ["show", write_file(t, "c.toml", case.replace(old, new)), "--out",
                                t / "v"], match)
    out = [
        Probe("interference", "period_1e-15", cli=False,
              call=lambda t: itf(chirp_period_s=[1e-15], ramp_time_s=[1e-16]),
              match=r"chirp_period_s=.*1e-15.*\[1e-06, 0\.01\]"),
        Probe("interference", "offset_1e300", cli=False, call=lambda t: itf(chirp_offset_s=[1e300]),
              match=r"chirp_offset_s=.*1e\+300.*\[-1, 1\] s"),
        Probe("interference", "offset_nan", cli=False,
              call=lambda t: itf(chirp_offset_s=[float("nan")]), match=r"chirp_offset_s.*finite"),
        Probe("interference", "power_-1e300", cli=False,
              call=lambda t: itf(tx_power_dbm=[-1e300]), match=r"tx_power_dbm=.*-1e\+300"),
        Probe("interference", "power_1e3", cli=False, call=lambda t: itf(tx_power_dbm=[1e3]),
              match=r"tx_power_dbm=.*1000"),
        Probe("interference", "gain_1e300", cli=False, call=lambda t: itf(tx_gain_dbi=[1e300]),
              match=r"tx_gain_dbi="),
        Probe("interference", "slope_1e300", cli=False,
              call=lambda t: itf(slope_hz_per_s=[1e300]), match=r"slope_hz_per_s="),
        Probe("interference", "start_freq_1e30", cli=False,
              call=lambda t: itf(start_freq_hz=[1e30]), match=r"start_freq_hz="),
        Probe("interference", "speed_1e300", cli=False,
              call=lambda t: itf(radial_velocity_mps=[1e300]), match=r"radial_velocity_mps="),
        Probe("interference", "range_1e300", cli=False,
              call=lambda t: itf(position_m=[[1e300, 0.0, 0.0]]), match=r"position_m|range"),
        Probe("interference", "equipment_offset_1e300", cli=False,
              call=lambda t: eq(chirp_offset_s=1e300), match=r"chirp_offset_s=1e\+300"),
        Probe("interference", "equipment_offset_nan", cli=False,
              call=lambda t: eq(chirp_offset_s=float("nan")), match=r"chirp_offset_s=nan"),
        Probe("interference", "equipment_power_-1e300", cli=False,
              call=lambda t: eq(tx_power_dbm=-1e300), match=r"tx_power_dbm=-1e\+300"),
        Probe("interference", "equipment_gain_-1e300", cli=False,
              call=lambda t: eq(antenna_gain_dbi=-1e300), match=r"antenna_gain_dbi=-1e\+300"),
        Probe("interference", "equipment_phase_1e300", cli=False,
              call=lambda t: eq(phase_rad=1e300), match=r"phase_rad=1e\+300"),
        Probe("interference", "equipment_exponent_1e300", cli=False,
              call=lambda t: eq(pattern_exponent_az=1e300), match=r"pattern_exponent_az"),
        case_probe("case_offset_1e300", "chirp_offset_s = 0.3e-6", "chirp_offset_s = 1e300",
                   r"radars\[0\].*chirp_offset_s=1e\+300"),
        case_probe("case_offset_nan", "chirp_offset_s = 0.3e-6", "chirp_offset_s = nan",
                   r"radars\[0\].*chirp_offset_s"),
        case_probe("case_power_-1e300", "tx_power_dbm = 12.0", "tx_power_dbm = -1e300",
                   r"radars\[0\].*tx_power_dbm=-1e\+300"),
        case_probe("case_offset_string", "chirp_offset_s = 0.3e-6", 'chirp_offset_s = "1 us"',
                   r"radars\[0\]\.chirp_offset_s"),
    ]
    return out


