"""Scenes shared by the chirp-level tests."""
from __future__ import annotations

import numpy as np

import radarsim
from radarsim import interference as itf_mod

#: Every chirp-level switch off: the plain windowed range FFT.
OFF = dict(dc_removal=False, interference_mitigation=False, compression=False)


def empty() -> radarsim.Scatterers:
    """No scatterers: thermal noise (and whatever interferers a test adds) only."""
    return radarsim.Scatterers(position_m=np.zeros((0, 3)), velocity_mps=np.zeros((0, 3)),
                               rcs_m2=[])


def one_interferer(slope=20e12, r=60.0, power_dbm=12.0) -> itf_mod.Interferers:
    """One FMCW interferer at `r` m (one-way power `power_dbm`, slope `slope` Hz/s)."""
    return itf_mod.Interferers(position_m=[[r, 5.0, 0.0]], radial_velocity_mps=[-5.0],
                               tx_gain_dbi=[10.0], start_freq_hz=[77.02e9],
                               slope_hz_per_s=[slope], chirp_period_s=[31e-6],
                               ramp_time_s=[25e-6], chirp_offset_s=[2e-6],
                               tx_power_dbm=[power_dbm])
