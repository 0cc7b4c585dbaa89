#!/usr/bin/env bash
# Run here, from the repository root, after `make test` or `make bench` has installed the packages: builds
# what a GPU machine without Debian's packages runs, mbao_bench and mbao_tests (no Python, no Embree), and
# gathers them into .gpu-bin with every shared library they load but the C and C++ runtimes (the GPU
# machine's own, newer ones serve), and the shared scenes into .gpu-scenes. The device tool carries both
# (carry: [".gpu-bin", ".gpu-scenes"]); bench/gpu/run.sh runs them there. docs/gpu.md says more.
set -euo pipefail
build="build-gpu-carry"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DMBAO_BUILD_PYTHON=OFF -DMBAO_BUILD_TESTS=ON \
      -DMBAO_BUILD_BENCH=ON -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON > /dev/null
cmake --build "$build" -j"$(nproc)" --target mbao_bench mbao_tests
rm -rf .gpu-bin && mkdir -p .gpu-bin/lib
cp "$build/bench/mbao_bench" "$build/tests/cpp/mbao_tests" .gpu-bin/
runtimes='/(libc|libm|libdl|libpthread|librt|libgcc_s|libstdc\+\+|ld-linux-x86-64)\.so'
ldd .gpu-bin/mbao_bench .gpu-bin/mbao_tests | awk '/=> \//{print $3}' | sort -u | { grep -Ev "$runtimes" || true; } |
  xargs -r cp -L -t .gpu-bin/lib
rm -rf .gpu-scenes && cp -r ../shared/scenes .gpu-scenes
du -sh .gpu-bin .gpu-scenes
