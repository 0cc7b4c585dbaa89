# The two commands: `make demo` and `make test`. Each installs what is missing
# (Debian packages, through apt-get), makes .venv on Debian's Python, builds,
# registers .venv as the Jupyter kernel "mbao", then renders or tests.
# Afterwards `.venv/bin/python -m mbao ...` works, and so does a headless run of
# a notebook (`.venv/bin/python -m nbconvert --to notebook --execute ...`).

PYTHON := /usr/bin/python3
VENV := .venv
BUILD := build
SANITIZE_BUILD := build-sanitize
JOBS := $(shell nproc)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
NODE_PACKAGES := nodejs npm
# The npm tools, each installed in its folder (below): `python -m mbao check`'s
# glTF-Validator, which the tests run too, and the tests' glTF-Transform.
GLTF_VALIDATOR := tools/gltf_validator/node_modules/.installed
NPM_TOOLS := $(GLTF_VALIDATOR) tests/gltf_transform/node_modules/.installed

# The C++ core and benchmark need only the first line; the rest is for the
# Python module, the tests, image files and running the notebooks headless.
APT_PACKAGES := cmake g++ make ocl-icd-opencl-dev opencl-c-headers opencl-clhpp-headers libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libassimp-dev libdraco-dev libmeshoptimizer-dev libeigen3-dev \
  pocl-opencl-icd pybind11-dev python3-pybind11 python3-dev python3-venv python3-pip python3-numpy python3-pytest \
  python3-pyopencl python3-openimageio python3-skbuild python3-nbclient python3-nbconvert python3-nbformat python3-ipykernel \
  python3-matplotlib python3-tqdm python3-pil python3-distributed python3-dask python3-aiohttp libgtest-dev

.PHONY: demo test bench corpus notebook notebook-kernel gltf-validator deps build sanitize-build clean

demo: build
	mkdir -p out
	$(VENV)/bin/python -m mbao render --bounces 1 -o out/cornell_b1.png
	$(VENV)/bin/python -m mbao render --bounces 2 -o out/cornell_b2.png

# Last, the sanitizer build's CTest: the C++ tests under AddressSanitizer and
# UBSan, and the glTF and Assimp loaders' fuzzers for 60 s each (fuzz/run_fuzzer.sh). Only
# the tests need clang, its sanitizer and libFuzzer runtimes and llvm-symbolizer
# (for readable reports): the target-specific value reaches `deps`.
SANITIZE_PACKAGES := clang libclang-rt-14-dev llvm
# The viewer's tests drive a real browser, headless, and Jupyter's notebook server.
BROWSER_TEST_PACKAGES := chromium chromium-driver python3-selenium python3-notebook
# mypy checks a typed script against the package's annotations, and its stubtest the core's stub.
TYPE_CHECK_PACKAGES := mypy
# The sources' format: clang-format's for C++ and OpenCL C, black's for Python (tests/test_formatting.py).
FORMAT_CHECK_PACKAGES := clang-format black
# The Blender add-on's tests run Debian's Blender (3.4) headless, and with a window under Xvfb.
BLENDER_TEST_PACKAGES := blender xvfb xauth
# CTest and pytest run a test per core (pytest through xdist's workers): kernel
# builds, which the driver's compiler runs on one core, and the tests that wait
# on a browser, a server or a child process overlap with the rest.
PARALLEL_TEST_PACKAGES := python3-pytest-xdist
test: APT_PACKAGES += $(SANITIZE_PACKAGES) $(BROWSER_TEST_PACKAGES) $(TYPE_CHECK_PACKAGES) $(BLENDER_TEST_PACKAGES) \
  $(PARALLEL_TEST_PACKAGES) $(FORMAT_CHECK_PACKAGES)
test: build sanitize-build $(NPM_TOOLS)
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)
	$(VENV)/bin/python -m pytest -n $(JOBS) tests
	cd $(SANITIZE_BUILD) && ctest --output-on-failure -j$(JOBS)

# The npm tools, each at the version its folder's package-lock.json pins,
# installed beside it: tools/gltf_validator, the Khronos glTF-Validator, which
# `python -m mbao check FILE` runs and the tests run on the files `mbao bake`
# writes (`make gltf-validator` installs it alone), and tests/gltf_transform,
# glTF-Transform's command line, which writes the quantized and compressed
# copies of the shared scenes the loading tests read. Node.js and npm come from
# Debian where the machine has no npm.
gltf-validator: $(GLTF_VALIDATOR)

%/node_modules/.installed: %/package.json %/package-lock.json
	command -v npm >/dev/null || { $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $(NODE_PACKAGES); }
	cd $* && npm ci --no-audit --no-fund
	touch $@

# The seed paper's Table 1 workload on the Cornell box and every shared scene,
# beside Embree 3. Embree is only the benchmark's: the target-specific value
# reaches `deps` through `build`, so only `make bench` installs it.
SCENES := ../shared/scenes
bench: APT_PACKAGES += libembree-dev
bench: build
	$(BUILD)/bench/mbao_bench --scenes $(SCENES) --json bench/results/latest.json

# Every model file under CORPUS loaded and rendered, beside what Assimp's own
# command line (Debian's assimp-utils, only this target's) and the Khronos
# validator say of it (tools/corpus_check.py): `make corpus CORPUS=folder`
# writes docs/corpus.md. docs/limits.md says which corpus it last ran on.
corpus: APT_PACKAGES += assimp-utils
corpus: build $(GLTF_VALIDATOR)
	$(VENV)/bin/python tools/corpus_check.py $(CORPUS) --report docs/corpus.md

# Jupyter's notebook server from Debian, started on notebooks/, whose kernel
# "mbao" `build` registered. Only this target (and `test`, for the viewer's
# tests) installs the server, which refuses root unless told (containers and
# CI machines run as root).
notebook: APT_PACKAGES += python3-notebook
notebook: build
	cd notebooks && $(PYTHON) -m notebook $(if $(SUDO),,--allow-root)

# The venv as the Jupyter kernel "mbao", which the notebooks name, in the
# user's Jupyter data directory ($$JUPYTER_DATA_DIR where set), for any Jupyter
# on the machine. It needs only ipykernel, not the notebook server, and works as
# root. `build` runs it, so the two commands leave the notebooks runnable.
# ipykernel install writes the spec into a folder it makes with mkdtemp and
# leaves that folder behind, empty: it gets a temporary folder of its own.
notebook-kernel: $(VENV)/bin/python
	scratch=$$(mktemp -d) && trap 'rm -rf "$$scratch"' EXIT && \
	  TMPDIR="$$scratch" $(VENV)/bin/python -m ipykernel install --user --name mbao --display-name "Python 3 (mbao)"

deps:
	@missing=$$(for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q "install ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "Installing missing Debian packages:" $$missing; \
	  $(SUDO) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq $$missing; \
	fi

$(VENV)/bin/python: | deps
	$(PYTHON) -m venv --system-site-packages $(VENV)

# The extension is built next to the Python sources and a .pth file puts
# python/ on the venv's path: an editable install that needs no rebuild of
# anything but what changed.
build: deps $(VENV)/bin/python notebook-kernel
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=$(PYTHON)
	cmake --build $(BUILD) -j$(JOBS)
	echo "$(CURDIR)/python" > "$$($(VENV)/bin/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/mbao-dev.pth"

# The C++ tests and the fuzzers, built by clang with AddressSanitizer and UBSan
# (tinygltf too, which mbao compiles from its header), without the Python module and the benchmark. At
# -O1 with line tables only, as the sanitizers' documentation advises: reports
# still name files and lines, and the build is shorter than with full debug info.
sanitize-build: APT_PACKAGES += $(SANITIZE_PACKAGES)
sanitize-build: deps
	cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
	  -DMBAO_SANITIZE=ON -DMBAO_BUILD_FUZZERS=ON -DMBAO_BUILD_PYTHON=OFF -DMBAO_BUILD_BENCH=OFF
	cmake --build $(SANITIZE_BUILD) -j$(JOBS)

clean:
	rm -rf $(BUILD) $(SANITIZE_BUILD) _skbuild python/mbao/_core*.so out
