#!/bin/sh
# Runs the glTF loader fuzzer for a fixed time from a fixed seed, as `make test`
# does (CTest's gltf_loader_fuzz in build-sanitize):
#
#   fuzz/run_gltf_fuzzer.sh build-sanitize/fuzz/gltf_loader_fuzzer [seconds]
#
# The committed seeds (fuzz/corpus, tests/data) are only read; the inputs the
# run adds go to a temporary directory and are dropped. Any finding (crash,
# sanitizer report, uncaught exception, an input running past -timeout seconds
# or -rss_limit_mb) stops the run with an error and is saved under
# ./gltf-findings/ to replay: `gltf_loader_fuzzer gltf-findings/crash-...`.
# The whole log goes to ./gltf_loader_fuzz.log; only the final statistics, or
# the end with the report, are printed, so that CTest's limit on test output
# cannot cut a report off.
set -eu
fuzzer=$1
seconds=${2:-60}
here=$(cd "$(dirname "$0")" && pwd)
new_inputs=$(mktemp -d)
trap 'rm -rf "$new_inputs"' EXIT
mkdir -p gltf-findings
if "$fuzzer" -seed=1 -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -dict="$here/gltf.dict" -artifact_prefix=gltf-findings/ -print_final_stats=1 \
  "$new_inputs" "$here/corpus" "$here/../tests/data" > gltf_loader_fuzz.log 2>&1; then
  grep -E '^(Done |stat::)' gltf_loader_fuzz.log
else
  status=$?
  tail -n 80 gltf_loader_fuzz.log
  echo "gltf_loader_fuzzer found a problem (exit $status); whole log: $(pwd)/gltf_loader_fuzz.log"
  exit "$status"
fi
