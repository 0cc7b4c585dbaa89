"""`pip install .` builds the C++ core (scikit-build + CMake) into a working package.

Slow (it compiles the core, a job per core): a minute or more.
"""

import os
import pathlib
import subprocess
import sys
import textwrap

REPO = pathlib.Path(__file__).resolve().parents[1]


def test_pip_install_gives_a_working_package(tmp_path):
    target = tmp_path / "site"
    # scikit-build runs `cmake --build` without -j: the environment asks for a job per core, as `make build` does.
    build_env = dict(os.environ, CMAKE_BUILD_PARALLEL_LEVEL=str(os.cpu_count()))
    install = subprocess.run(
        [sys.executable, "-m", "pip", "install", "--no-build-isolation", "--no-deps", "--no-input",
         "--target", str(target), str(REPO)],
        capture_output=True, text=True, timeout=600, env=build_env,
    )  # fmt: skip
    assert install.returncode == 0, f"pip install failed:\n{install.stdout[-4000:]}\n{install.stderr[-4000:]}"
    assert list((target / "mbao").glob("_core*.so")), sorted(p.name for p in (target / "mbao").iterdir())
    from mbao.viewer.server import STATIC_FILES

    assert all((target / "mbao" / "viewer" / "static" / name).is_file() for name in STATIC_FILES)
    assert (target / "mbao" / "py.typed").is_file() and (target / "mbao" / "_core.pyi").is_file()  # PEP 561
    assert (target / "mbao" / "blender" / "mbao_bake" / "operator.py").is_file()  # what `mbao blender` installs

    check = textwrap.dedent(
        """
        import pathlib, sys
        import mbao, mbao._core
        target = pathlib.Path(sys.argv[1]).resolve()
        assert target in pathlib.Path(mbao.__file__).resolve().parents, mbao.__file__
        assert target in pathlib.Path(mbao._core.__file__).resolve().parents, mbao._core.__file__
        result = mbao.render(mbao.cornell_box(), width=8, height=8)
        assert result.ao.shape == (8, 8) and result.mask.any(), result
        assert result.stats["rays_primary"] == 64
        print("ok", mbao.__file__)
        """
    )
    # cwd and PYTHONPATH are the install folder, so the source tree's python/ is not what gets imported.
    env = dict(os.environ, PYTHONPATH=str(target))
    proc = subprocess.run(
        [sys.executable, "-c", check, str(target)], capture_output=True, text=True, timeout=300, cwd=target, env=env
    )
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert proc.stdout.startswith("ok " + str(target)), proc.stdout
