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
from radarsim.ti import parse_ti_cfg, to_ti_cfg
from tests.radarsim.profiles import PROFILE_DIR, profile_text

C = 299_792_458.0

XWR18_VISUALIZER = profile_text("xwr18_visualizer")

# ROS driver / SDK 2.x style xWR16xx profile: no Platform header (the chip follows from the
# complex ADC and the Tx1/Tx2 mask), a 33.333 ms frame.
XWR16_ROS = profile_text("xwr16_ros")

# IWR6843ISK, SDK 3.5 demo profile style, Tx1 and Tx3 only (txChannelEn 5), 60 GHz.
XWR68_TX13 = profile_text("xwr68_tx13")

# xWR14xx, SDK 1.1 Visualizer style (TI ROS driver 1443_3d.cfg): no subFrameIdx, interleaved
# ADC buffer (the xwr14xx demo's only mode).
XWR14_SDK1 = profile_text("xwr14_sdk1_visualizer")

# AWR294X MCU+ SDK TDM demo, profile_LVDS.cfg style: real ADC, non-interleaved buffer for the
# DCA1000, frameCfg with numAdcSamples, the EVM antGeometryCfg, Tx4 disabled.
AWR2944_TDM_LVDS = profile_text("awr2944_tdm_lvds")

# AWR2x44P DDM demo style: 5-argument channelCfg, 12/13-argument cfarCfg, DDM order and array.
AWR2944P_DDM = profile_text("awr2944p_ddm")

# AWR2544 DDM demo style: procChainCfg, 3-argument dither and analog-monitor commands, a DDM
# order without an elevation Tx, no Platform header.
AWR2544_DDM = profile_text("awr2544_ddm")

# Industrial toolbox people-counting lab style on the IWR6843ISK: lab commands, a second
# profile and chirps the frame does not use.
XWR68_PEOPLE_COUNTING = profile_text("xwr68_people_counting")

# mmWave SDK 1.x xWR16xx syntax: adcbufCfg and guiMonitor without subFrameIdx, cfarCfg with a
# linear threshold.
XWR16_SDK1 = profile_text("xwr16_sdk1")


# TI Visualizer 3.6 output for an AOP board: "% Platform:xWR68xx_AOP" (the chip of the base
# name; the AOP antenna is not in the board registry, the ISK's is assumed unless the profile
# gives antGeometryCfg) and a ramp sized to the 64 GHz band edge with the ramp end time rounded
# to 10 ns: 60 GHz + 70 MHz/us x 57.15 us = 64.0005 GHz, within one slope x 10 ns of the edge.
XWR68_AOP = profile_text("xwr68_aop")

# TI Visualizer 2.0 (mmWave SDK 2.0) xWR16xx output: ChirpThreshold 0, 8-argument cfarCfg
# with a linear threshold, nearFieldCfg, and a user's trailing "#" note.
XWR16_SDK2 = profile_text("xwr16_sdk2")

# Industrial-toolbox people-counting lab for the IWR1642 (toolbox 3.x): SDK 1.x adcbufCfg, the
# lab firmware's own guiMonitor/cfarCfg syntax and tracker commands.
XWR16_LAB = profile_text("xwr16_lab")


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
    # B = 70 x 240 / 5 = 3360 MHz; Tc = 257.15 us; 3 x 16 = 48 chirps; the AOP grid
    # (radarsim.boards: z = 0 row Tx2/Tx3 x Rx2/Rx4, raised rows at 1, 0.5, -0.5 lambda).
    "xwr68xx_aop_visualizer": (
        XWR68_AOP, "IWR6843", "IWR6843AOPEVM", "complex1x", "tdma", 3, 4, (1, 2, 3), (1, 2, 3), 48,
        C / (2 * 3360e6), 5e6 * C / (2 * 70e12),
        _lam(60) / (4 * 3 * 257.15e-6), _lam(60) / (2 * 48 * 257.15e-6), 0.033333,
        ([0, 1, 2, 3], [0, 0, 0, 1, 1, 1, 2, 3], [0.5, 1, 0.5, 1, -0.5, -0.5, -0.5, -0.5])),
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
    # xWR14xx SDK 1.1 Visualizer (interleaved buffer): B = 68 x 256 / 5.5 = 3165.1 MHz;
    # Tc = 7 + 58 = 65 us; 3 x 16 = 48 chirps, Tx order Tx1, Tx3, Tx2 (masks 1, 4, 2).
    "xwr14xx_sdk1_visualizer": (
        XWR14_SDK1, "AWR1443", "AWR1443BOOST", "complex1x", "tdma", 3, 4, (1, 2, 3), (1, 3, 2),
        48, C / (2 * 68e12 * 256 / 5.5e6), 5.5e6 * C / (2 * 68e12),
        _lam(77) / (4 * 3 * 65e-6), _lam(77) / (2 * 48 * 65e-6), 0.033333,
        (list(range(8)), [2, 3, 4, 5], 0.5)),
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
    assert sorted(lay.v_pos) == v_pos
    assert np.allclose(lay.v_height_wl, v_h)
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
    assert {"dynamicRACfarCfg", "trackingCfg", "sensorPosition", "antGeometry0"} \
        <= set(prof.ignored_commands)
    # compRangeBiasAndRxChanPhase is applied (pipeline.compensation), not ignored.
    assert "compRangeBiasAndRxChanPhase" not in prof.ignored_commands
    assert prof.processing["channel_comp"][:2] == ((1.0, 0.0), (-1.0, 0.0))
    assert any("chirps [3]" in n for n in prof.notes)
    assert any("profiles [1]" in n for n in prof.notes)
    prof = parse_ti_cfg(XWR18_VISUALIZER)
    assert {"bpmCfg", "lvdsStreamCfg"} <= set(prof.ignored_commands)
    unmodelled = [n for n in prof.notes if n.startswith("read but not modelled: ")]
    assert len(unmodelled) == 1 and "CQRxSatMonitor" in unmodelled[0]
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
    "awr1642_third_tx": (XWR16_ROS, "channelCfg 15 3 0", "% Platform:xWR16xx\nchannelCfg 15 7 0",
                         r"txChannelEn=7 is outside 1..3 \(AWR1642"),
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


def test_mcu_plus_sdk_0407_awr294x_profile_with_five_argument_channel_cfg():
    """MCU+ SDK 04.07 AWR294X profiles carry channelCfg <rx> <tx> <cascading> <ethOscClkEn>
    <driveStrength> (cli_mmwave.c, the AWR2x44P form the 04.07 AWR294X demo shares): accepted
    on the AWR2944 with a note. B = 70 x 656 / 13.349 = 3439.9 MHz; Tc = 186 + 57.14 =
    243.14 us; 4 Tx x 64 loops = 256 chirps; TDMA Vmax = lambda / (4 x 4 x Tc)."""
    prof = parse_ti_cfg(profile_text("awr294x_sdk0407_tdm"))
    cfg = prof.radar
    assert (cfg.chip, cfg.mimo, cfg.n_tx, cfg.tx_order, cfg.n_chirps) == ("AWR2944", "tdma", 4,
                                                                          (1, 3, 4, 2), 256)
    assert cfg.range_resolution_m == pytest.approx(C / (2 * 70e12 * 656 / 13.349e6), rel=1e-9)
    assert cfg.max_unambiguous_velocity_mps == pytest.approx(_lam(77) / (16 * 243.14e-6),
                                                             rel=1e-9)
    assert prof.demo_family == "mcu_plus_tdm" and prof.processing["tdma_disambiguation"]
    assert any("ethOscClkEn/driveStrength (MCU+ SDK 04.07 AWR294X form)" in n
               for n in prof.notes)
    with pytest.raises(ValueError, match=r"line \d+ \(channelCfg\): the 5-argument form .* the "
                                         r"AWR1843 demo takes 3 arguments"):
        parse_ti_cfg(XWR18_VISUALIZER.replace("channelCfg 15 7 0", "channelCfg 15 7 0 0 0"))


@pytest.mark.parametrize("name", sorted(p.stem for p in PROFILE_DIR.glob("*.cfg")))
def test_written_profile_means_the_same(name):
    """to_ti_cfg writes a profile's radar, CFAR and processing commands (its demo family's):
    reading it back gives the same radar, CFAR and ProcessingConfig values, per sub-frame."""
    prof = parse_ti_cfg(profile_text(name))
    back = parse_ti_cfg(to_ti_cfg(prof))
    for a, b in zip(prof.parts, back.parts, strict=True):
        assert (a.radar, a.cfar, a.processing, a.demo_family) == \
            (b.radar, b.cfar, b.processing, b.demo_family)


def test_occupancy_profile_of_128_loops_of_four_chirps_is_written_in_its_own_form():
    """TI's xWR18xx occupancy-detection form: Tx1, Tx3, Tx1, Tx3 per loop, 128 loops (512
    chirps). Written back with one Tx per slot it would need 256 loops of 2 (the AWR1843
    counts 255): the writer repeats the slot sequence per loop, as the profile does."""
    prof = parse_ti_cfg(profile_text("xwr18_occupancy_4zone"))
    r = prof.radar
    assert (r.chip, r.mimo, r.n_tx, r.tx_channels, r.n_chirps) == ("AWR1843", "tdma", 2,
                                                                   (1, 3), 512)
    text = to_ti_cfg(prof)
    lines = text.splitlines()
    assert [ln for ln in lines if ln.startswith("chirpCfg")] == [
        "chirpCfg 0 0 0 0 0 0 0 1", "chirpCfg 1 1 0 0 0 0 0 4",
        "chirpCfg 2 2 0 0 0 0 0 1", "chirpCfg 3 3 0 0 0 0 0 4"]
    assert "frameCfg 0 3 128 0 150 1 0" in lines
    assert parse_ti_cfg(text).radar == r
    # A bare config of the same frame is written the same way.
    assert "frameCfg 0 3 128 0 150 1 0" in to_ti_cfg(r, frame_period_s=0.15)


def test_a_frame_no_loop_repetition_fits_is_refused():
    """514 TDMA chirps of 2 Tx: 257 loops of 2, and 257 is prime: no repetition of the
    sequence fits the 512 chirp definitions and 255 loops."""
    r = parse_ti_cfg(profile_text("xwr18_occupancy_4zone")).radar.replace(n_chirps=514)
    with pytest.raises(ValueError, match="n_chirps=514: 257 loops of 2 chirps exceed the "
                                         "AWR1843 frame limit of 255 loops"):
        to_ti_cfg(r)
