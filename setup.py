# scikit-build drives CMake for `pip install --no-build-isolation .`; the
# metadata is in pyproject.toml.
from skbuild import setup

setup(
    packages=["mbao", "mbao.viewer", "mbao.blender", "mbao.blender.mbao_bake"],
    package_data={"mbao": ["py.typed", "_core.pyi"], "mbao.viewer": ["static/*"]},
    package_dir={"": "python"},
    cmake_install_dir="python",
    cmake_args=["-DMBAO_BUILD_TESTS=OFF", "-DMBAO_BUILD_BENCH=OFF", "-DMBAO_PYTHON_INPLACE=OFF"],
)
