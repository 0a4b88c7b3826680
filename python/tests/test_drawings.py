"""The drawings as an independent DXF reader sees them (ezdxf, not the `dxf` crate that
wrote them): every shipped scene's `<name>-drawing.dxf` passes ezdxf's audit without an
error, is in millimetres, and its DIMENSION entities are real dimensions — each draws its
block, and the measurement it carries is what ezdxf measures from its definition points."""

import math

import pytest

ezdxf = pytest.importorskip("ezdxf")


@pytest.fixture(scope="module")
def drawings(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("drawings")
    run = cli("batch", "problems/", "--out", out, "--quiet")
    assert run.returncode == 0, run.stderr
    found = sorted(out.glob("*-drawing.dxf"))
    assert len(found) >= 20, found
    return found


def test_every_drawing_audits_clean_and_its_dimensions_measure_what_they_say(drawings):
    for path in drawings:
        doc = ezdxf.readfile(path)
        auditor = doc.audit()
        assert not auditor.has_errors, (path.name, [str(e.message) for e in auditor.errors])
        assert doc.header["$INSUNITS"] == 4, path.name  # millimetres
        dims = doc.modelspace().query("DIMENSION")
        assert len(dims) > 0, path.name
        for dim in dims:
            block = dim.get_geometry_block()
            assert block is not None and len(block) > 0, (path.name, dim.dxf.geometry)
            said = dim.dxf.actual_measurement
            measured = dim.get_measurement()
            if dim.dimtype in (2, 5):  # angular: ezdxf measures in degrees
                said = math.degrees(said)
            assert math.isclose(said, measured, rel_tol=1e-9, abs_tol=1e-9), (
                path.name,
                dim.dxf.geometry,
                said,
                measured,
            )
