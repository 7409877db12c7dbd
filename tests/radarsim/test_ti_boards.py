"""Board geometry a TI profile implies: ``% Platform:xWR68xx_AOP`` is the IWR6843AOPEVM's
antenna-on-package grid (`radarsim.boards`, from TI's Industrial Toolbox ``antGeometry0/1``),
and the chains estimate azimuth and elevation on it."""
import numpy as np
import pytest

import pipeline
import radarsim
from harness.cell.ti_profile import processing_from_profile, simulation_radar
from radarsim.ti import parse_ti_cfg, to_ti_cfg
from tests.radarsim.profiles import profile_text

#: TI mmWave Industrial Toolbox 4.7.0, 3D people counting, AOP_6m_default.cfg (chirps Tx0, Tx1,
#: Tx2; lambda/2 units): azimuth and elevation index of each virtual element.
AOP_ANT_GEOMETRY0 = (-1, -1, 0, 0, -3, -3, -2, -2, -1, -1, 0, 0)
AOP_ANT_GEOMETRY1 = (-1, 0, -1, 0, -3, -2, -3, -2, -3, -2, -3, -2)
#: The same lab's ISK_6m_default.cfg: the ISK layout the SDK documents, read the same way.
ISK_ANT_GEOMETRY0 = (0, -1, -2, -3, -2, -3, -4, -5, -4, -5, -6, -7)
ISK_ANT_GEOMETRY1 = (-1, -1, -1, -1, 0, 0, 0, 0, -1, -1, -1, -1)


def _indices(cfg):
    """(m, n) of each virtual element in Tx-channel-major order, lambda/2 units, referred to
    the first element: m = -2 y / lambda, n = 2 z / lambda."""
    order = np.argsort(np.repeat(np.array(cfg.tx_order), cfg.n_rx), kind="stable")
    pos = cfg.virtual_positions_m[order] / (cfg.wavelength_m / 2)
    m, n = np.rint(-pos[:, 1]).astype(int), np.rint(pos[:, 2]).astype(int)
    return m - m[0], n - n[0]


@pytest.mark.parametrize("profile, board, geo0, geo1", [
    ("xwr68_aop", "IWR6843AOPEVM", AOP_ANT_GEOMETRY0, AOP_ANT_GEOMETRY1),
    ("xwr68_people_counting", "IWR6843ISK", ISK_ANT_GEOMETRY0, ISK_ANT_GEOMETRY1),
])
def test_platform_header_gives_the_board_ti_describes(profile, board, geo0, geo1):
    prof = parse_ti_cfg(profile_text(profile))
    assert prof.radar.board == board
    m, n = _indices(prof.radar)
    np.testing.assert_array_equal(m, np.array(geo0) - geo0[0])
    np.testing.assert_array_equal(n, np.array(geo1) - geo1[0])


def test_platform_header_of_another_chips_board_is_refused():
    """A ``% radarsim: chip`` directive for an AWR1843 above the AOP header (a board carrying
    an IWR6843) contradicts it: the reader names the header line, not RadarConfig later."""
    text = '% radarsim: chip = "AWR1843"\n' + profile_text("xwr68_aop")
    with pytest.raises(ValueError, match=r"line 5: '% Platform:xWR68xx_AOP' means board "
                                         r"IWR6843AOPEVM, which carries a IWR6843, not the "
                                         r"profile's chip AWR1843"):
        parse_ti_cfg(text)


def test_written_profile_keeps_the_aop_board():
    prof = parse_ti_cfg(profile_text("xwr68_aop"))
    text = to_ti_cfg(prof)
    assert "% Platform:xWR68xx_AOP" in text.splitlines()
    assert parse_ti_cfg(text).radar == prof.radar


@pytest.mark.parametrize("az, el", [(0.0, 0.0), (25.0, -10.0), (-40.0, 20.0), (10.0, 45.0),
                                    (0.0, -50.0)])
def test_tdma_chain_estimates_both_angles_on_the_aop_grid(az, el):
    """A 3 m target seen by the AOP board the profile's line calibrates (Rx2/Rx4 in
    antiphase, `simulation_radar`): azimuth from the 4-element z = 0 row, elevation from the
    three raised rows (0.5 lambda rows first, then the 1 lambda row unwrapped), both within
    1.5 deg (design.md's point-target tolerance) at ~45 dB."""
    prof = parse_ti_cfg(profile_text("xwr68_aop"))
    proc = processing_from_profile(prof).replace(velocity_fov_mps=None)
    sc = radarsim.Scatterers.from_spherical(np.array([3.0]), np.array([az]), np.array([el]),
                                            np.zeros(1), np.array([0.01]))
    adc = radarsim.simulate_frame(simulation_radar(prof), sc, np.random.default_rng(3))
    pc = pipeline.process_frame(prof.radar, adc, proc)
    best = pc.loc[pc.snr_db.idxmax()]
    assert abs(best.azimuth_deg - az) <= 1.5 and abs(best.elevation_deg - el) <= 1.5, best


@pytest.mark.parametrize("v", [0.5, 1.6, -1.8, 3.0])
def test_velocity_extension_on_the_aop_grid(v):
    """extendedMaxVelocity on the AOP board (Vmax 1.62 m/s, span +/-4.86): targets off
    boresight in both planes are reported at their speed (within 0.1 m/s): the hypothesis
    likelihood ties the three raised rows by one elevation (`stages.array_likelihood`)."""
    prof = parse_ti_cfg(profile_text("xwr68_aop"))
    proc = processing_from_profile(prof).replace(tdma_disambiguation=True,
                                                 velocity_fov_mps=None)
    radar = simulation_radar(prof)
    rng = np.random.default_rng(5)
    for az, el in ((0.0, 0.0), (20.0, 10.0), (-30.0, -15.0), (40.0, 25.0), (-10.0, -40.0)):
        sc = radarsim.Scatterers.from_spherical(np.array([3.0]), np.array([az]),
                                                np.array([el]), np.array([v]),
                                                np.array([0.01]))
        pc = pipeline.process_frame(prof.radar, radarsim.simulate_frame(radar, sc, rng), proc)
        best = pc.loc[pc.snr_db.idxmax()]
        assert abs(best.radial_velocity_mps - v) < 0.1, (az, el, best.radial_velocity_mps)
