"""One definition of each setting: the core's tables (cpp/render/setting_specs.h)
give mbao.render's signature, defaults and docstring, mbao.Engine's fields, the
settings classes' signatures, reprs and pickles, and docs/spec.md's tables
(the bake's: test_bake.py; the command line's: test_cli.py)."""

import inspect
import pathlib
import pickle
import re

import numpy as np
import pytest

import mbao


@pytest.fixture(scope="module")
def cornell():
    return mbao.cornell_box()


ENGINE_KNOBS = ("traversal", "organisation", "tile_pixels", "work_group_size", "traversal_stats")


def test_render_lists_the_users_settings_with_the_tables_defaults():
    parameters = inspect.signature(mbao.render).parameters
    specs = {spec["name"]: spec for spec in mbao._core.setting_specs()}
    assert not set(ENGINE_KNOBS) & set(parameters), "engine settings belong in engine=mbao.Engine(...)"
    for name, spec in specs.items():
        if spec["group"] == "render":
            assert parameters[name].default == spec["default"], name
            assert f"{name}: {spec['doc'].split()[0]}" in mbao.render.__doc__, f"{name} is not documented"
        else:
            assert getattr(mbao.Engine(), name) == spec["default"], name
            assert f"{name}: " in mbao.Engine.__doc__, f"{name} is not documented"
    assert {"camera", "hbao", "engine", "device", "progress"} <= set(parameters)


def test_the_defaults_are_the_cores(cornell):
    """A render with no settings and one with every default spelt out are the same render."""
    specs = mbao._core.setting_specs()
    spelt_out = {spec["name"]: spec["default"] for spec in specs if spec["group"] == "render"}
    spelt_out.update(width=6, height=5, seed=4)
    engine = mbao.Engine(**{spec["name"]: spec["default"] for spec in specs if spec["group"] == "engine"})
    a = mbao.render(cornell, engine=engine, **spelt_out)
    b = mbao.render(cornell, width=6, height=5, seed=4)
    np.testing.assert_array_equal(a.ao, b.ao)
    assert a.stats["kernel_options"] == b.stats["kernel_options"]


@pytest.mark.parametrize("cls", [mbao.HBAO, mbao.Denoise, mbao.Temporal])
def test_the_cores_settings_classes_have_real_signatures_whose_defaults_they_take(cls):
    """inspect.signature (help(), IDEs, notebooks' completion) reads a core class
    as it is called; each default is what the constructor gives."""
    parameters = inspect.signature(cls).parameters
    made = cls()
    assert parameters and all(getattr(made, name) == p.default for name, p in parameters.items())


@pytest.mark.parametrize("cls, table", [(mbao.HBAO, "hbao"), (mbao.Denoise, "denoise"), (mbao.Temporal, "temporal")])
def test_the_cores_settings_classes_are_their_tables(cls, table):
    """One table per class (cpp/render/setting_specs.h) names its parameters in
    order, gives their defaults, documents each, and makes its repr and pickle."""
    specs = mbao._core.setting_specs(table)
    parameters = inspect.signature(cls).parameters
    assert list(parameters) == [spec["name"] for spec in specs]
    assert [p.default for p in parameters.values()] == pytest.approx([spec["default"] for spec in specs])
    for spec in specs:
        assert f"{spec['name']}: {spec['doc']}" in cls.__doc__ and f"allowed {spec['range']}." in cls.__doc__
    made = cls(**{spec["name"]: spec["hi"] if spec["kind"] == "integer" else spec["lo"] + 0.5 for spec in specs})
    again = eval("mbao." + repr(made))
    assert pickle.loads(pickle.dumps(made)) is not made
    assert [getattr(again, s["name"]) for s in specs] == [getattr(made, s["name"]) for s in specs]
    assert [getattr(pickle.loads(pickle.dumps(made)), s["name"]) for s in specs] == [
        getattr(made, s["name"]) for s in specs
    ]


@pytest.mark.parametrize("table", ["render", "hbao", "bake", "denoise", "temporal"])
def test_the_spec_shows_each_settings_table_as_the_core_has_it(table):
    """docs/spec.md's tables of a render's (3.5), HBAO's (4), the bake's own
    (6), the denoiser's (7.3) and temporal accumulation's (7.4) settings are
    mbao.settings.markdown_table's, which prints the one to paste where they
    differ."""
    spec = (pathlib.Path(__file__).resolve().parents[1] / "docs" / "spec.md").read_text()
    assert mbao.settings.markdown_table(table) in spec, mbao.settings.markdown_table(table)


def test_a_camera_has_a_real_signature_and_a_repr_that_makes_it_again():
    signature = inspect.signature(mbao.Camera)
    assert list(signature.parameters) == ["eye", "target", "up", "vfov_deg", "max_distance"]
    camera = mbao.Camera((0.0, 1.0, 5.0), (0.0, 0.0, 0.0))
    assert [camera.up, camera.vfov_deg, camera.max_distance] == [
        tuple(signature.parameters["up"].default),
        signature.parameters["vfov_deg"].default,
        None,
    ]
    suggesting = mbao.Camera((0.0, 1.0, 5.0), (0.0, 0.0, 0.0), max_distance=2.5)
    again = eval("mbao." + repr(suggesting))
    assert (again.eye, again.target, again.max_distance) == (suggesting.eye, suggesting.target, 2.5)
    assert "does not use it" not in mbao.Camera.__doc__ and "max_distance_source" in mbao.Camera.__doc__


@pytest.mark.parametrize("cls, maker", [(mbao.Scene, "mbao.load"), (mbao.Device, "mbao.devices()")])
def test_classes_made_elsewhere_say_where_when_called(cls, maker):
    assert not inspect.signature(cls).parameters
    with pytest.raises(TypeError, match=re.escape(maker)):
        cls()


def test_a_mesh_keeps_its_own_signature():
    assert list(inspect.signature(mbao.Mesh).parameters) == ["vertices", "indices", "normals", "texcoords"]


def test_engine_keywords_of_render_still_work_for_one_release(cornell):
    settings = dict(width=8, height=8, bounces=2, seed=3)
    with pytest.warns(DeprecationWarning, match=r"engine=mbao.Engine\(traversal=...\)"):
        old = mbao.render(cornell, traversal="restart", **settings)
    new = mbao.render(cornell, engine=mbao.Engine(traversal="restart"), **settings)
    assert old.stats["traversal_mode"] == new.stats["traversal_mode"] == "restart"
    np.testing.assert_array_equal(old.ao, new.ao)
    with pytest.raises(TypeError, match="beside engine="):
        mbao.render(cornell, engine=mbao.Engine(), traversal="restart", **settings)


def test_an_engine_is_checked_when_it_is_made():
    with pytest.raises(ValueError, match="organisation must be one of"):
        mbao.Engine(organisation="queue")
    assert mbao.Engine(tile_pixels=np.int64(9)).tile_pixels == 9
    assert "traversal='stack'" in repr(mbao.Engine(traversal="stack"))
