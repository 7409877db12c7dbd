"""Shared pieces of the OpenSCENARIO tests: the ASAM schema and the hand-written files."""
from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import qc_openscenario
from lxml import etree

#: The hand-written test files (OpenSCENARIO + their OpenDRIVE road).
DATA = Path(__file__).resolve().parents[2] / "data" / "openscenario"
ELK = DATA / "elk_overtaking_motorbike.xosc"
ALKS = DATA / "alks_side_motorbike.xosc"
ROAD = DATA / "motorway_3lane.xodr"


@pytest.fixture(scope="session")
def osc_schema():
    """The ASAM OpenSCENARIO 1.2 XSD, as shipped by the ASAM quality checker's package."""
    xsd = Path(qc_openscenario.__file__).parent / "schema" / "1.2.0" / "OpenSCENARIO.xsd"
    return etree.XMLSchema(etree.parse(str(xsd)))


@pytest.fixture
def scene_dir(tmp_path):
    """A folder with the road and the ALKS file's text to edit: ``write(text) -> path``."""
    shutil.copy(ROAD, tmp_path / ROAD.name)

    def write(text: str, name: str = "scene.xosc") -> Path:
        p = tmp_path / name
        p.write_text(text)
        return p
    write.text = ALKS.read_text()
    write.dir = tmp_path
    return write
