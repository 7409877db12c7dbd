"""Signal-chain benchmark: process_frame time against an FFT floor, SNR gains, shifter spurs,
ghosts and masking versus phase error."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import pipeline
import radarsim
from harness.runtime import tune_allocator
from pipeline.kernels import doppler_fft, range_fft, window

from ._timing import chain_against_floor, median_time_s


def _scene(targets) -> radarsim.Scatterers:
    return radarsim.Scatterers.from_spherical(*np.atleast_2d(np.asarray(targets, float)).T)


def _ghosts_and_misses(cfg, n_frames, rng) -> tuple[float, float]:
    """A strong target (~70 dB detection SNR) with four weak ones (~25 dB) in its range bin at
    random velocities and angles: detections matching no target (ghosts) and weak targets not
    detected (misses), per frame."""
    ghosts = misses = 0
    for _ in range(n_frames):
        r0 = rng.uniform(10, 20)
        tg = [[r0, rng.uniform(-30, 30), 0, rng.uniform(-20, 20), 300.0]]
        tg += [[r0 + rng.uniform(-0.3, 0.3), rng.uniform(-50, 50), 0, rng.uniform(-35, 35), 0.02]
               for _ in range(4)]
        pc = pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, _scene(tg), rng))
        true = np.zeros(len(pc), bool)
        for r, _az, _el, v, _ in tg:
            match = ((pc.range_m - r).abs() < 2.0) & ((pc.radial_velocity_mps - v).abs() < 0.3)
            misses += int(not match.any())
            true |= match
        ghosts += int((~true).sum())
    return ghosts / n_frames, misses / n_frames


def _spur_dbc(cfg, tx: int) -> float:
    """Strongest empty-sub-band line relative to the Tx's own line, Tx `tx` alone (the others
    muted through their gain error), Doppler spectrum (Rx1) of one strong target at boresight,
    ~90 dB over the noise after the FFTs (design.md 8: -34.5 dBc for the 60/120 deg-step Tx, none
    for the 0 and 180 deg ones)."""
    gains = tuple(0.0 if t == tx else -300.0 for t in range(1, cfg.n_tx + 1))
    one = cfg.replace(**{"impairments.tx_gain_error_db": gains})
    sc = _scene([[20.0, 0.0, 0.0, 0.0, 2e5]])  # ~2000 LSB: ADC rounding far below -34 dBc
    adc = radarsim.simulate_frame(one, sc, np.random.default_rng(0))
    # Hann in range keeps the real ADC's mirror tone (whose Doppler line is the conjugate,
    # i.e. in the last sub-band) out of the target's range bin; rectangular in Doppler keeps
    # the on-grid lines exact.
    spec = doppler_fft(range_fft(adc, window("hann", cfg.n_samples)),
                       window("boxcar", cfg.n_chirps))
    r0 = int(np.argmax((np.abs(spec[:, 0]) ** 2).sum(axis=0)))  # the target's range bin
    bands = (np.abs(spec[:, 0, r0]) ** 2).reshape(cfg.n_subbands, -1)
    return 10 * np.log10(bands[cfg.n_tx:].max() / bands.max())


_TARGETS = [[15, 20, 0, -12, 10], [45, -30, 2, 15, 10], [90, 5, 0, -30, 10],
            [150, 40, -3, 5, 10], [60, -10, 0, 8, 1]]


def _frames() -> dict:
    """One R79 frame per scheme of a five-target scene (fixed seed)."""
    rng = np.random.default_rng(0)
    out = {}
    for preset in ("r79_ddma", "r79_tdma"):
        cfg = radarsim.presets.PRESETS[preset]()
        out[preset] = cfg, radarsim.simulate_frame(cfg, _scene(_TARGETS), rng)
    return out


def _default_allocator_medians() -> dict[str, float]:
    """process_frame medians in a fresh interpreter with glibc's default allocator settings
    (mallopt is process-wide and cannot be undone here)."""
    root = Path(__file__).resolve().parents[1]
    res = subprocess.run([sys.executable, "-m", "benchmarks.bench_pipeline",
                          "--default-allocator"], cwd=root, capture_output=True, text=True)
    try:
        return json.loads(res.stdout.strip().splitlines()[-1])
    except (IndexError, json.JSONDecodeError):
        return {}


def run() -> list[str]:
    out = []
    rng = np.random.default_rng(1)
    default = _default_allocator_medians()
    tuned = tune_allocator()  # as radar-harness and the sweep workers run (benchmarks/__main__)
    for preset, (cfg, adc) in _frames().items():
        t = chain_against_floor(cfg, adc)
        out.append(f"process_frame {cfg.mimo.upper()}: best cpu {1e3 * t.chain.cpu_s:6.1f} ms, "
                   f"wall {1e3 * t.chain.wall_s:6.1f} ms ({'tuned' if tuned else 'default'} "
                   f"allocator; glibc default median wall "
                   f"{1e3 * default.get(preset, float('nan')):5.1f} ms), FFT floor cpu (one "
                   f"core) {1e3 * t.floor_cpu_s:4.1f} ms, wall {1e3 * t.floor_wall_s:4.1f} ms: "
                   f"{t.cpu_ratio:4.1f}x CPU, {t.wall_ratio:4.1f}x wall")
    d, t = radarsim.presets.r79_ddma(), radarsim.presets.r79_tdma()
    gains = []
    for _ in range(16):
        tg = [[rng.uniform(30, 150), rng.uniform(-40, 40), 0.0, rng.uniform(-9, 9), 30.0]]
        snr = []
        for cfg in (d, t):
            pc = pipeline.process_frame(cfg, radarsim.simulate_frame(cfg, _scene(tg), rng))
            near = pc[(pc.range_m - tg[0][0]).abs() < 2]
            snr.append(near.snr_db.max() if len(near) else np.nan)
        gains.append(snr[0] - snr[1])
    out.append(f"detection-SNR gain DDMA - TDMA: median {np.nanmedian(gains):.2f} dB over "
               f"{np.isfinite(gains).sum()} targets (6.02 dB energy - demodulation bias)")
    noise_adc = radarsim.simulate_frame(d, radarsim.Scatterers.empty(), rng)
    raw = doppler_fft(range_fft(noise_adc, window("hann", d.n_samples)),
                      window("hann", d.n_chirps))
    power, _, _ = pipeline.detection_map(d, noise_adc)
    bias = 10 * np.log10(power[1:].mean() / (12 * np.mean(np.abs(raw[:, :, 1:]) ** 2)))
    out.append(f"empty-band demodulation noise-floor bias: {bias:.2f} dB (mean power)")

    for q in ("floor", "round"):
        dq = d.replace(shifter={"phase_quantization": q})
        spurs = ", ".join(f"Tx{t} {_spur_dbc(dq, t):6.1f}" for t in (1, 3, 4, 2))
        out.append(f"6-bit shifter ({q}) empty-band spur, dBc of the Tx line: {spurs} "
                   "(about -80: the noise floor)")
    for label, key, values in [("random per-chirp phase error", "phase_noise_deg_rms",
                                (0.0, 2.0, 5.0, 10.0, 20.0)),
                               ("static per-Tx phase error", "tx_phase_error_deg",
                                (0.0, 2.0, 10.0, 20.0))]:
        for err in values:
            value = err if key == "phase_noise_deg_rms" else (0.0, err, -err, 0.5 * err)
            g, m = _ghosts_and_misses(d.replace_fields(**{key: value}), 8, np.random.default_rng(1))
            out.append(f"{label} {err:4.1f} deg: {g:5.2f} ghosts/frame, {m:4.2f} of 4 weak "
                       "targets missed/frame (strong + 4 weak in one range bin, 8 frames)")
    return out


if __name__ == "__main__" and "--default-allocator" in sys.argv:
    print(json.dumps({p: median_time_s(lambda c=c, a=a: pipeline.process_frame(c, a),
                                       repeats=41) for p, (c, a) in _frames().items()}))
