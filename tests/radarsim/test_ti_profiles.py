"""Real-world TI profile styles for every chip family, with derived values computed by hand.

Each profile below is written for these tests, modelled on a public style (the commands, their
argument counts and their order): TI Visualizer 3.5 output for xWR18xx, the mmWave SDK
xwr16xx/xwr68xx demo profiles (``profile_2d.cfg``) and the ROS driver's copies, the AWR294X MCU+
SDK ``profile_LVDS.cfg`` (TDM), the AWR2x44P and AWR2544 DDM demo profiles, an industrial
toolbox people-counting lab and the mmWave SDK 1.x syntax. Hand computations use
c = 299792458 m/s, lambda = c / f_start, B = S N / f_s, range resolution c / 2B, max range
N/2 (real) or N (complex) x resolution, TDMA Vmax = lambda / (4 Nt Tc), DDMA Vmax =
lambda / (4 Tc), velocity resolution lambda / (2 N_chirps Tc).
"""
from __future__ import annotations

import numpy as np
import pytest

from pipeline.kernels import array_layout
from radarsim.ti_cfg import parse_ti_cfg, to_ti_cfg

C = 299_792_458.0

XWR18_VISUALIZER = """\
% ***************************************************************
% Created for SDK ver:03.05
% Created using Visualizer ver:3.5.0.0
% Frequency:77
% Platform:xWR18xx
% Scene Classifier:best_range_res
% ***************************************************************
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 7 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
profileCfg 0 77 267 7 57.14 0 0 70 1 256 5209 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 4
chirpCfg 2 2 0 0 0 0 0 2
frameCfg 0 2 16 0 100 1 0
lowPower 0 0
guiMonitor -1 1 1 0 0 0 1
cfarCfg -1 0 2 8 4 3 0 15 1
cfarCfg -1 1 0 4 2 3 1 15 1
multiObjBeamForming -1 1 0.5
clutterRemoval -1 0
calibDcRangeSig -1 0 -5 8 256
extendedMaxVelocity -1 0
bpmCfg -1 0 0 1
lvdsStreamCfg -1 0 1 0
compRangeBiasAndRxChanPhase 0.0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0
measureRangeBiasAndRxChanPhase 0 1.5 0.2
CQRxSatMonitor 0 3 5 121 0
CQSigImgMonitor 0 127 4
analogMonitor 0 0
aoaFovCfg -1 -90 90 -90 90
cfarFovCfg -1 0 0 11.15
cfarFovCfg -1 1 -1 1.00
calibData 0 0 0
sensorStart
"""

# ROS driver / SDK 2.x style xWR16xx profile: no Platform header (the chip follows from the
# complex ADC and the Tx1/Tx2 mask), a 33.333 ms frame.
XWR16_ROS = """\
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 3 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
profileCfg 0 77 429 7 57.14 0 0 70 1 240 4884 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 2
frameCfg 0 1 32 0 33.333 1 0
lowPower 0 0
guiMonitor -1 1 1 1 0 0 1
cfarCfg -1 0 2 8 4 3 0 15 1
cfarCfg -1 1 0 4 2 3 1 15 1
peakGrouping -1 1 1 1 1 229
multiObjBeamForming -1 1 0.5
clutterRemoval -1 0
calibDcRangeSig -1 0 -5 8 256
extendedMaxVelocity -1 0
compRangeBiasAndRxChanPhase 0.0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0
measureRangeBiasAndRxChanPhase 0 1.5 0.2
CQRxSatMonitor 0 3 5 123 0
CQSigImgMonitor 0 115 6
analogMonitor 1 1
sensorStart
"""

# IWR6843ISK, SDK 3.5 demo profile style, Tx1 and Tx3 only (txChannelEn 5), 60 GHz.
XWR68_TX13 = """\
% Platform:xWR68xx
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 5 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
profileCfg 0 60 567 7 57.14 0 0 70 1 256 5209 0 0 158
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 4
frameCfg 0 1 16 0 100 1 0
lowPower 0 0
guiMonitor -1 1 1 0 0 0 1
cfarCfg -1 0 2 8 4 3 0 15 1
cfarCfg -1 1 0 4 2 3 1 15 1
multiObjBeamForming -1 1 0.5
clutterRemoval -1 0
calibDcRangeSig -1 0 -5 8 256
extendedMaxVelocity -1 0
bpmCfg -1 0 0 1
lvdsStreamCfg -1 0 0 0
compRangeBiasAndRxChanPhase 0.0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0
measureRangeBiasAndRxChanPhase 0 1.5 0.2
CQRxSatMonitor 0 3 5 121 0
CQSigImgMonitor 0 127 4
analogMonitor 0 0
aoaFovCfg -1 -90 90 -90 90
cfarFovCfg -1 0 0 8.92
cfarFovCfg -1 1 -1 1.00
calibData 0 0 0
sensorStart
"""

# AWR294X MCU+ SDK TDM demo, profile_LVDS.cfg style: real ADC, non-interleaved buffer for the
# DCA1000, frameCfg with numAdcSamples, the EVM antGeometryCfg, Tx4 disabled.
AWR2944_TDM_LVDS = """\
% Created for SDK ver:04.01
% Platform:AWR294X
% CFG TYPE: LVDS streaming enabled
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 7 0
adcCfg 2 0
adcbufCfg -1 1 1 1 1
lowPower 0 0
profileCfg 0 77 267 7 57.14 0 0 70 1 448 10000 0 0 158
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 4
chirpCfg 2 2 0 0 0 0 0 2
frameCfg 0 2 32 20 448 100 1 0
lowPower 0 0
guiMonitor -1 1 1 0 0 0 1
cfarCfg -1 0 2 8 4 3 0 15 1
cfarCfg -1 1 0 4 2 3 1 15 1
multiObjBeamForming -1 1 0.5
calibDcRangeSig -1 0 -5 8 256
clutterRemoval -1 0
antGeometryCfg 1 0 1 1 1 2 1 3 0 2 0 3 0 4 0 5 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 0.5 0.8
compRangeBiasAndRxChanPhase 0.0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0
measureRangeBiasAndRxChanPhase 0 1.5 0.2
aoaFovCfg -1 -90 90 -90 90
cfarFovCfg -1 0 0 10.7
cfarFovCfg -1 1 -1 1.00
extendedMaxVelocity -1 0
calibData 0 0 0x1f0000
CQRxSatMonitor 0 3 11 121 0
CQSigImgMonitor 0 127 8
analogMonitor 0 0
lvdsStreamCfg -1 0 1 0
sensorStart
"""

# AWR2x44P DDM demo style: 5-argument channelCfg, 12/13-argument cfarCfg, DDM order and array.
AWR2944P_DDM = """\
% Platform:AWR2X44P
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 15 0 0 0
adcCfg 2 0
adcbufCfg -1 1 0 0 1
lowPower 0 0
profileCfg 0 77 5 6 20 0 0 15 0 256 25000 0 0 36
chirpCfg 0 5 0 0 0 0 0 15
frameCfg 0 5 64 0 256 100 1 0
guiMonitor -1 1 0 0 0 0 0
cfarCfg -1 0 3 16 0 0 1 15.0 0 7 0 0
cfarCfg -1 1 3 16 0 0 1 12.0 0 24 0 1 0
compressionCfg -1 1 0 0.5 8
intfMitigCfg -1 15 18
localMaxCfg -1 4 40
ddmPhaseShiftAntOrder 0 2 3 1
antGeometryCfg 1 0 1 1 1 2 1 3 0 2 0 3 0 4 0 5 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 0.5 0.8
antennaCalibParams 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1 0 1
aoaFovCfg -1 -70 70 -20 20
measureRangeBiasAndRxChanPhase 0 1.5 0.2
analogMonitor 0 0
calibData 0 0 0
sensorStart
"""

# AWR2544 DDM demo style: procChainCfg, 3-argument dither and analog-monitor commands, a DDM
# order without an elevation Tx, no Platform header.
AWR2544_DDM = """\
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 15 0 0 0
adcCfg 2 0
adcbufCfg -1 1 0 1 1
lowPower 0 0
profileCfg 0 77 7 7 20.81 0 0 8.883 0 256 30000 0 0 164
chirpCfg 0 5 0 0 0 0 0 15
frameCfg 0 5 128 0 256 50 1 0
compressionCfg -1 1 0 0.5 8
intfMitigCfg -1 15 18
procChainCfg 1 0 530 0 1
ddmPhaseShiftAntOrder 0 1 2 3
adcDataDitherCfg 0 0 1
analogMonitor 0 0 0
calibData 0 0 0
sensorStart
"""

# Industrial toolbox people-counting lab style on the IWR6843ISK: lab commands, a second
# profile and chirps the frame does not use.
XWR68_PEOPLE_COUNTING = """\
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 7 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
lowPower 0 0
profileCfg 0 60.75 30.00 25.00 59.10 0 0 54.71 1 96 2950.00 0 0 30
profileCfg 1 60.75 30.00 25.00 59.10 0 0 54.71 1 96 2950.00 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 2
chirpCfg 2 2 0 0 0 0 0 4
chirpCfg 3 3 1 0 0 0 0 1
frameCfg 0 2 96 0 55.00 1 0
dynamicRACfarCfg -1 4 4 2 2 8 12 4 12 5.00 8.00 0.40 1 1
staticRACfarCfg -1 6 2 2 2 8 8 6 4 8.00 15.00 0.30 0 0
dynamicRangeAngleCfg -1 0.75 0.0010 1 0
dynamic2DAngleCfg -1 3.0 0.0300 1 0 1 0.30 0.85 8.00
staticRangeAngleCfg -1 0 8 8
antGeometry0 -1 -1 0 0 -3 -3 -2 -2 -1 -1 0 0
antGeometry1 -1 0 -1 0 -3 -2 -3 -2 -3 -2 -3 -2
antPhaseRot 1 -1 1 -1 1 -1 1 -1 1 -1 1 -1
fovCfg -1 70.0 70.0
compRangeBiasAndRxChanPhase 0.0 1.00000 0.00000 -1.00000 0.00000 1.00000 0.00000 -1.00000 0.00000 1.00000 0.00000 -1.00000 0.00000 1.00000 0.00000 -1.00000 0.00000 1.00000 0.00000 -1.00000 0.00000 1.00000 0.00000 -1.00000 0.00000
staticBoundaryBox -3 3 0.5 7.5 0 3
boundaryBox -4 4 0 8 0 3
sensorPosition 2 0 15
gatingParam 3 2 2 3 4
stateParam 3 3 12 500 5 6000
allocationParam 40 100 0.1 20 0.5 20
maxAcceleration 0.1 0.1 0.1
trackingCfg 1 2 800 30 46 96 55
presenceBoundaryBox -3 3 0.5 7.5 0 3
sensorStart
"""

# mmWave SDK 1.x xWR16xx syntax: adcbufCfg and guiMonitor without subFrameIdx, cfarCfg with a
# linear threshold.
XWR16_SDK1 = """\
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 3 0
adcCfg 2 1
adcbufCfg 0 1 1 1
profileCfg 0 77 100 6 60 0 0 60 1 256 5000 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 2
frameCfg 0 1 64 0 50 1 0
guiMonitor 1 1 0 0 0 1
cfarCfg 0 2 8 4 3 0 1280
peakGrouping 1 0 1 1 229
multiObjBeamForming 1 0.5
calibDcRangeSig 0 -5 8 256
sensorStart
"""


# TI Visualizer 3.6 output for an AOP board: "% Platform:xWR68xx_AOP" (the chip of the base
# name; the AOP antenna is not in the board registry, the ISK's is assumed unless the profile
# gives antGeometryCfg) and a ramp sized to the 64 GHz band edge with the ramp end time rounded
# to 10 ns: 60 GHz + 70 MHz/us x 57.15 us = 64.0005 GHz, within one slope x 10 ns of the edge.
XWR68_AOP = """\
% Created for SDK ver:03.05
% Created using Visualizer ver:3.6.0.0
% Frequency:60
% Platform:xWR68xx_AOP
flushCfg
dfeDataOutputMode 1
channelCfg 15 7 0
adcCfg 2 1
adcbufCfg -1 0 1 1 1
profileCfg 0 60 200 7 57.15 0 0 70 1 240 5000 0 0 158
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 2
chirpCfg 2 2 0 0 0 0 0 4
frameCfg 0 2 16 0 33.333 1 0
lowPower 0 0
guiMonitor -1 1 0 0 0 0 1
cfarCfg -1 0 2 8 4 3 0 15 1
cfarCfg -1 1 0 4 2 3 1 15 1
lvdsStreamCfg -1 0 0 0
compRangeBiasAndRxChanPhase 0.0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0 1 0 -1 0
CQRxSatMonitor 0 3 11 119 0
CQSigImgMonitor 0 89 6
analogMonitor 0 0
cfarFovCfg -1 1 -1.21 1.21
calibData 0 0 0
sensorStart
"""

# TI Visualizer 2.0 (mmWave SDK 2.0) xWR16xx output: ChirpThreshold 0, 8-argument cfarCfg
# with a linear threshold, nearFieldCfg, and a user's trailing "#" note.
XWR16_SDK2 = """\
% Created for SDK ver:02.00
% Platform:xWR16xx
sensorStop
flushCfg
dfeDataOutputMode 1
channelCfg 15 3 0
adcCfg 2 1
adcbufCfg -1 0 0 1 0
profileCfg 0 77 40 7 57.14 0 0 70 1 256 5209 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 2
frameCfg 0 1 16 0 33.333 1 0
lowPower 0 1
guiMonitor -1 1 0 0 0 0 0
cfarCfg -1 0 0 8 4 4 0 3072
cfarCfg -1 1 0 4 2 3 0 3072
peakGrouping -1 1 0 1 1 255
clutterRemoval -1 1 # static clutter off in the lab
bpmCfg -1 0 0 1
nearFieldCfg -1 0 0 0
analogMonitor 1 1
sensorStart
"""

# Industrial-toolbox people-counting lab for the IWR1642 (toolbox 3.x): SDK 1.x adcbufCfg, the
# lab firmware's own guiMonitor/cfarCfg syntax and tracker commands.
XWR16_LAB = """\
dfeDataOutputMode 1
channelCfg 15 3 0
adcCfg 2 1
adcbufCfg 0 1 1 1
profileCfg 0 77 35 7 62 0 0 60 1 128 2500 0 0 30
chirpCfg 0 0 0 0 0 0 0 1
chirpCfg 1 1 0 0 0 0 0 2
frameCfg 0 1 64 0 50 1 0
lowPower 0 1
guiMonitor 1 1 0 0
cfarCfg 6 4 4 4 4 16 16 4 4 50 62 0
doaCfg 600 1875 30 1
SceneryParam -6 6 0.05 6
GatingParam 4 3 2 0
StateParam 10 5 10 100 5
AllocationParam 450 0.01 25 1 2
VariationParam 0.289 0.289 1.0
PointCloudEn 1
trackingCfg 1 2 250 20 200 50 90
sensorStart
"""


def _lam(f_ghz: float) -> float:
    return C / (f_ghz * 1e9)


# name: (text, chip, board, adc_mode, mimo, n_tx, n_rx, tx_channels, tx_order, n_chirps,
#        range_res_m, max_range_m, vmax_mps, vres_mps, frame_period_s,
#        (horizontal virtual positions in lambda/2, raised positions, raised height in lambda))
PROFILES = {
    # B = 70 MHz/us x 256 / 5.209 Msps = 3440.2 MHz; Tc = 267 + 57.14 = 324.14 us;
    # 3 Tx x 16 loops = 48 chirps; complex: max range = 256 x res = 5.209e6 c / (2 x 70e12).
    "xwr18xx_visualizer": (
        XWR18_VISUALIZER, "AWR1843", "AWR1843BOOST", "complex1x", "tdma", 3, 4, (1, 2, 3),
        (1, 3, 2), 48, C / (2 * 70e12 * 256 / 5.209e6), 5.209e6 * C / (2 * 70e12),
        _lam(77) / (4 * 3 * 324.14e-6), _lam(77) / (2 * 48 * 324.14e-6), 0.1,
        (list(range(8)), [2, 3, 4, 5], 0.5)),
    # B = 70 x 240 / 4.884 = 3439.8 MHz; Tc = 486.14 us; 2 Tx x 32 = 64 chirps.
    "xwr16xx_ros": (
        XWR16_ROS, "AWR1642", "AWR1642BOOST", "complex1x", "tdma", 2, 4, (1, 2), (1, 2), 64,
        C / (2 * 70e12 * 240 / 4.884e6), 4.884e6 * C / (2 * 70e12),
        _lam(77) / (4 * 2 * 486.14e-6), _lam(77) / (2 * 64 * 486.14e-6), 0.033333,
        (list(range(8)), [], 0.0)),
    # 60 GHz: lambda = 4.997 mm; Tx1 + Tx3 (txChannelEn 5) 2 lambda apart: 8 contiguous
    # lambda/2 elements; Tc = 624.14 us; 2 x 16 = 32 chirps.
    "xwr68xx_tx1_tx3": (
        XWR68_TX13, "IWR6843", "IWR6843ISK", "complex1x", "tdma", 2, 4, (1, 3), (1, 2), 32,
        C / (2 * 70e12 * 256 / 5.209e6), 5.209e6 * C / (2 * 70e12),
        _lam(60) / (4 * 2 * 624.14e-6), _lam(60) / (2 * 32 * 624.14e-6), 0.1,
        (list(range(8)), [], 0.0)),
    # Real: B = 70 x 448 / 10 = 3136 MHz, max range = 224 x res = 5e6 c / (2 x 70e12);
    # 3 Tx x 32 = 96 chirps; Tx2 raised 0.8 lambda over positions 2..5.
    "awr294x_tdm_lvds": (
        AWR2944_TDM_LVDS, "AWR2944", "AWR2944EVM", "real", "tdma", 3, 4, (1, 2, 3), (1, 3, 2),
        96, C / (2 * 70e12 * 448 / 10e6), 5e6 * C / (2 * 70e12),
        _lam(77) / (4 * 3 * 324.14e-6), _lam(77) / (2 * 96 * 324.14e-6), 0.1,
        (list(range(8)), [2, 3, 4, 5], 0.8)),
    # B = 15 MHz/us x 10.24 us = 153.6 MHz; 6 sub-bands x 64 = 384 chirps of 25 us;
    # DDMA Vmax = lambda / (4 Tc).
    "awr2x44p_ddm": (
        AWR2944P_DDM, "AWR2944P", "AWR2944PEVM", "real", "ddma", 4, 4, (1, 2, 3, 4),
        (1, 3, 4, 2), 384, C / (2 * 153.6e6), 12.5e6 * C / (2 * 15e12),
        _lam(77) / (4 * 25e-6), _lam(77) / (2 * 384 * 25e-6), 0.1,
        (list(range(12)), [2, 3, 4, 5], 0.8)),
    # B = 8.883 x 256 / 30 = 75.80 MHz; Tc = 27.81 us; 6 x 128 = 768 chirps; order 0 1 2 3.
    "awr2544_ddm": (
        AWR2544_DDM, "AWR2544", "AWR2544LOPEVM", "real", "ddma", 4, 4, (1, 2, 3, 4),
        (1, 2, 3, 4), 768, C / (2 * 8.883e12 * 256 / 30e6), 15e6 * C / (2 * 8.883e12),
        _lam(77) / (4 * 27.81e-6), _lam(77) / (2 * 768 * 27.81e-6), 0.05,
        (list(range(16)), [], 0.0)),
    # 60.75 GHz; B = 54.71 x 96 / 2.95 = 1780.4 MHz; Tc = 89.1 us; 3 x 96 = 288 chirps.
    "xwr68xx_people_counting": (
        XWR68_PEOPLE_COUNTING, "IWR6843", "IWR6843ISK", "complex1x", "tdma", 3, 4, (1, 2, 3),
        (1, 2, 3), 288, C / (2 * 54.71e12 * 96 / 2.95e6), 2.95e6 * C / (2 * 54.71e12),
        _lam(60.75) / (4 * 3 * 89.1e-6), _lam(60.75) / (2 * 288 * 89.1e-6), 0.055,
        (list(range(8)), [2, 3, 4, 5], 0.5)),
    # B = 70 x 240 / 5 = 3360 MHz; Tc = 257.15 us; 3 x 16 = 48 chirps; ISK array assumed.
    "xwr68xx_aop_visualizer": (
        XWR68_AOP, "IWR6843", "IWR6843ISK", "complex1x", "tdma", 3, 4, (1, 2, 3), (1, 2, 3), 48,
        C / (2 * 3360e6), 5e6 * C / (2 * 70e12),
        _lam(60) / (4 * 3 * 257.15e-6), _lam(60) / (2 * 48 * 257.15e-6), 0.033333,
        (list(range(8)), [2, 3, 4, 5], 0.5)),
    # B = 70 x 256 / 5.209 = 3440.2 MHz; Tc = 97.14 us; 2 x 16 = 32 chirps.
    "xwr16xx_sdk2_visualizer": (
        XWR16_SDK2, "AWR1642", "AWR1642BOOST", "complex1x", "tdma", 2, 4, (1, 2), (1, 2), 32,
        C / (2 * 70e12 * 256 / 5.209e6), 5.209e6 * C / (2 * 70e12),
        _lam(77) / (4 * 2 * 97.14e-6), _lam(77) / (2 * 32 * 97.14e-6), 0.033333,
        (list(range(8)), [], 0.0)),
    # B = 60 x 128 / 2.5 = 3072 MHz; Tc = 97 us; 2 x 64 = 128 chirps.
    "xwr16xx_people_counting_lab": (
        XWR16_LAB, "AWR1642", "AWR1642BOOST", "complex1x", "tdma", 2, 4, (1, 2), (1, 2), 128,
        C / (2 * 3072e6), 2.5e6 * C / (2 * 60e12),
        _lam(77) / (4 * 2 * 97e-6), _lam(77) / (2 * 128 * 97e-6), 0.05,
        (list(range(8)), [], 0.0)),
    # B = 60 x 256 / 5 = 3072 MHz; Tc = 160 us; 2 x 64 = 128 chirps.
    "xwr16xx_sdk1": (
        XWR16_SDK1, "AWR1642", "AWR1642BOOST", "complex1x", "tdma", 2, 4, (1, 2), (1, 2), 128,
        C / (2 * 3072e6), 5e6 * C / (2 * 60e12),
        _lam(77) / (4 * 2 * 160e-6), _lam(77) / (2 * 128 * 160e-6), 0.05,
        (list(range(8)), [], 0.0)),
}


@pytest.mark.parametrize("name", sorted(PROFILES))
def test_real_profile_styles_are_accepted_with_hand_computed_values(name):
    (text, chip, board, adc_mode, mimo, n_tx, n_rx, chans, order, n_chirps, res, rmax, vmax,
     vres, period, (h_pos, v_pos, v_h)) = PROFILES[name]
    prof = parse_ti_cfg(text)
    cfg = prof.radar
    assert (cfg.chip, cfg.board, cfg.adc_mode, cfg.mimo) == (chip, board, adc_mode, mimo)
    assert (cfg.n_tx, cfg.n_rx, cfg.tx_channels, cfg.tx_order) == (n_tx, n_rx, chans, order)
    assert cfg.n_chirps == n_chirps
    assert cfg.range_resolution_m == pytest.approx(res, rel=1e-9)
    assert cfg.max_range_m == pytest.approx(rmax, rel=1e-9)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(vmax, rel=1e-9)
    assert cfg.velocity_resolution_mps == pytest.approx(vres, rel=1e-9)
    assert prof.frame_period_s == pytest.approx(period, rel=1e-12)
    lay = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    assert list(lay.h_pos) == h_pos
    assert sorted(lay.v_pos) == v_pos and lay.v_height_wl == pytest.approx(v_h)
    assert cfg.n_virtual == n_tx * n_rx
    # Every command is used or kept; the writer reproduces the radar exactly.
    assert parse_ti_cfg(to_ti_cfg(prof)).radar == cfg


def test_hand_values_of_the_xwr18xx_profile_in_numbers():
    """The same values as plain numbers (TI Visualizer's header figures for such a profile)."""
    cfg = parse_ti_cfg(XWR18_VISUALIZER).radar
    assert cfg.range_resolution_m == pytest.approx(0.04357, abs=1e-5)
    assert cfg.max_range_m == pytest.approx(11.155, abs=1e-3)
    assert cfg.n_range_bins == 256
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(1.0010, abs=1e-4)
    assert cfg.velocity_resolution_mps == pytest.approx(0.1251, abs=1e-4)


def test_ignored_commands_and_notes_are_reported():
    prof = parse_ti_cfg(XWR68_PEOPLE_COUNTING)
    assert {"dynamicRACfarCfg", "trackingCfg", "sensorPosition", "antGeometry0",
            "compRangeBiasAndRxChanPhase"} <= set(prof.ignored_commands)
    assert any("chirps [3]" in n for n in prof.notes)
    assert any("profiles [1]" in n for n in prof.notes)
    prof = parse_ti_cfg(XWR18_VISUALIZER)
    assert {"bpmCfg", "lvdsStreamCfg", "CQRxSatMonitor", "calibDcRangeSig",
            "compRangeBiasAndRxChanPhase"} <= set(prof.ignored_commands)
    assert prof.lvds_stream == (False, 1, False)


@pytest.mark.parametrize("seq, order", [
    ((1, 4, 1, 4), (1, 2)),       # Tx1, Tx3 alternating twice per loop
    ((4, 1), (2, 1)),             # Tx3 first
    ((1, 4, 2), (1, 3, 2)),       # three Tx, the raised one last
])
def test_tdma_chirp_orders(seq, order):
    chirps = "\n".join(f"chirpCfg {i} {i} 0 0 0 0 0 {m}" for i, m in enumerate(seq))
    text = XWR18_VISUALIZER.replace(
        "chirpCfg 0 0 0 0 0 0 0 1\nchirpCfg 1 1 0 0 0 0 0 4\nchirpCfg 2 2 0 0 0 0 0 2\n"
        "frameCfg 0 2 16 0 100 1 0", chirps + f"\nframeCfg 0 {len(seq) - 1} 16 0 100 1 0")
    cfg = parse_ti_cfg(text).radar
    assert cfg.tx_order == order and cfg.n_chirps == 16 * len(seq)
    assert cfg.tx_channels == tuple(sorted({m.bit_length() for m in seq}))


def test_tdma_sequence_with_a_repeated_tx_is_refused():
    text = XWR18_VISUALIZER.replace("chirpCfg 2 2 0 0 0 0 0 2", "chirpCfg 2 2 0 0 0 0 0 1")
    no = next(k for k, line in enumerate(text.splitlines(), 1) if line.startswith("frameCfg"))
    with pytest.raises(ValueError, match=rf"line {no} .*matches no MIMO scheme"):
        parse_ti_cfg(text)


def test_complex_frame_samples_count_16_bit_words():
    """rlFrameCfg_t.numAdcSamples is 2 x the profile's samples for complex data."""
    text = AWR2944_TDM_LVDS  # real: frameCfg says 448 = profileCfg's 448
    assert parse_ti_cfg(text).radar.n_samples == 448
    bad = text.replace("frameCfg 0 2 32 20 448 100", "frameCfg 0 2 32 20 896 100")
    with pytest.raises(ValueError, match=r"numAdcSamples=896 differs from profileCfg's "
                                         r"numAdcSamples=448"):
        parse_ti_cfg(bad)


CHIP_REFUSALS = {
    # kind: (profile, old, new, message)
    "iwr6843_at_77ghz": (XWR68_TX13, "profileCfg 0 60 ", "profileCfg 0 77 ",
                         r"startFreq=77 GHz is outside the IWR6843 band 60..64 GHz"),
    "iwr6843_ramp_beyond_64ghz": (XWR68_TX13, "profileCfg 0 60 ", "profileCfg 0 60.5 ",
                                  r"exceeds the IWR6843 band limit 6.4e\+10 Hz"),
    "awr1642_third_tx": (XWR16_ROS, "channelCfg 15 3 0", "channelCfg 15 3 0\n% Platform:xWR16xx"
                         "\nchannelCfg 15 7 0", r"txChannelEn=7 is outside 1..3 \(AWR1642"),
    "awr1843_complex_rate": (XWR18_VISUALIZER, " 256 5209 ", " 256 13000 ",
                             r"adc_rate_sps=1.3e\+07 exceeds the AWR1843 limit .*complex1x"),
    "awr1843_interleaved_buffer": (XWR18_VISUALIZER, "adcbufCfg -1 0 1 1 1",
                                   "adcbufCfg -1 0 1 0 1",
                                   r"AWR1843 demo supports only the non-interleaved"),
    "awr1642_ddma_without_shifter": (XWR16_ROS, "chirpCfg 0 0 0 0 0 0 0 1\n"
                                     "chirpCfg 1 1 0 0 0 0 0 2", "chirpCfg 0 1 0 0 0 0 0 3",
                                     r"needs per-Tx phase shifters; the AWR1642 has none"),
    "awr1843_ddm_order_size": (XWR18_VISUALIZER, "lowPower 0 0", "ddmPhaseShiftAntOrder 0 2 1 3",
                               r"expects 3 arguments, got 4"),
}


@pytest.mark.parametrize("kind", sorted(CHIP_REFUSALS))
def test_chip_limits_refuse_with_the_line(kind):
    text, old, new, pattern = CHIP_REFUSALS[kind]
    assert old in text
    with pytest.raises(ValueError, match=pattern) as err:
        parse_ti_cfg(text.replace(old, new, 1))
    assert str(err.value).startswith("line ")


def test_ant_geometry_defines_the_array():
    """A grid with Tx2 at 1.5 lambda (col 3) and 0.5 lambda up (zSpacebylambda 0.5) moves the
    raised row to positions 3..6, 0.5 lambda high."""
    geo = ("antGeometryCfg 1 0 1 1 1 2 1 3 0 3 0 4 0 5 0 6 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 "
           "0.5 0.5")
    text = AWR2944_TDM_LVDS.replace(
        "antGeometryCfg 1 0 1 1 1 2 1 3 0 2 0 3 0 4 0 5 1 4 1 5 1 6 1 7 1 8 1 9 1 10 1 11 0.5 0.8",
        geo)
    cfg = parse_ti_cfg(text).radar
    assert cfg.tx_positions_wl[1] == (1.5, 0.5)
    lay = array_layout(cfg.virtual_positions_m, cfg.wavelength_m)
    assert sorted(lay.v_pos) == [3, 4, 5, 6] and lay.v_height_wl == pytest.approx(0.5)
    assert parse_ti_cfg(to_ti_cfg(cfg)).radar == cfg
    np.testing.assert_allclose(cfg.virtual_positions_m[:, 0], 0.0)


def test_sdk_bpm_profile_is_the_bpm_scheme():
    """mmWave SDK ``profile_2d_bpm.cfg`` style: two chirps enabling Tx1+Tx2, ``bpmCfg -1 1 0 1``
    (chirp 0: +,+; chirp 1: +,-) is the harness's 2 x 2 Hadamard BPM: Vmax = lambda / (4 x 2 Tc)
    as TDMA; it writes back as itself."""
    text = XWR16_ROS.replace("chirpCfg 0 0 0 0 0 0 0 1\nchirpCfg 1 1 0 0 0 0 0 2",
                             "chirpCfg 0 0 0 0 0 0 0 3\nchirpCfg 1 1 0 0 0 0 0 3") \
        .replace("clutterRemoval -1 0", "clutterRemoval -1 0\nbpmCfg -1 1 0 1")
    prof = parse_ti_cfg(text)
    cfg = prof.radar
    assert (cfg.mimo, cfg.n_tx, cfg.tx_order, cfg.n_chirps) == ("bpm", 2, (1, 2), 64)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(_lam(77) / (4 * 2 * 486.14e-6))
    assert "bpmCfg -1 1 0 1" in to_ti_cfg(prof)
    assert parse_ti_cfg(to_ti_cfg(prof)).radar == cfg
