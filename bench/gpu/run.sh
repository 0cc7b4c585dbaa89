#!/usr/bin/env bash
# Run there, on a GPU machine the device tool lent, from the repository root with .gpu-bin and .gpu-scenes
# carried (bench/gpu/prepare.sh made them here). Registers NVIDIA's OpenCL, then
#   bench/gpu/run.sh bench [RESULT [SECTIONS]]  the benchmark into $OUT/RESULT.json (default nvidia-h200,
#                                               the sections of the committed GPU runs), its log beside it;
#   bench/gpu/run.sh tests                      the C++ tests in six shards at once, logs in $OUT.
# The device is $MBAO_DEVICE (an index or part of a name), NVIDIA's where it is not set.
set -euo pipefail
out=${OUT:?"OUT names the folder that comes back (the device tool sets it)"}
device=${MBAO_DEVICE:-NVIDIA}

# The image registers only PoCL; NVIDIA's library is beside the driver (docs/gpu.md, step 3).
nvidia=$(ls /usr/local/nvidia/lib64/libnvidia-opencl.so.1 2> /dev/null ||
         find /usr /opt -name libnvidia-opencl.so.1 -print -quit 2> /dev/null || true)
if [ -n "$nvidia" ]; then
  mkdir -p /etc/OpenCL/vendors && echo "$nvidia" > /etc/OpenCL/vendors/nvidia.icd
fi
export LD_LIBRARY_PATH=$PWD/.gpu-bin/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export MBAO_SHARED_SCENES=$PWD/.gpu-scenes

case ${1:-} in
  bench)
    result=${2:-nvidia-h200}
    sections=${3:-table1,profile,traversals,masks,kernel-builds,loading,organisation,kd-build}
    # Into a file, not a pipe: a benchmark whose output pipe closes dies before writing its JSON.
    if ! .gpu-bin/mbao_bench --device "$device" --scenes .gpu-scenes --sections "$sections" \
        --work-groups 32,64,128,256 --json "$out/$result.json" > "$out/$result.log" 2>&1; then
      tail -n 30 "$out/$result.log"
      exit 1
    fi
    tail -n 5 "$out/$result.log" ;;
  tests)
    # NVIDIA compiles each kernel variant the tests use: six processes at once share the work.
    failed=0
    for shard in 0 1 2 3 4 5; do
      MBAO_DEVICE=$device GTEST_TOTAL_SHARDS=6 GTEST_SHARD_INDEX=$shard .gpu-bin/mbao_tests \
        > "$out/tests-$shard.log" 2>&1 &
    done
    for shard in 0 1 2 3 4 5; do wait -n || failed=1; done
    grep -h -E '^\[  (PASSED|FAILED|SKIPPED) ' "$out"/tests-*.log || true
    exit $failed ;;
  *)
    echo "usage: bench/gpu/run.sh bench [RESULT [SECTIONS]] | tests" >&2
    exit 2 ;;
esac
