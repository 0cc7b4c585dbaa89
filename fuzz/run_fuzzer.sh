#!/bin/sh
# Runs one of the loader fuzzers for a fixed time from a fixed seed, as `make
# test` does (CTest's *_fuzz tests in build-sanitize):
#
#   fuzz/run_fuzzer.sh build-sanitize/fuzz/gltf_loader_fuzzer [seconds] [seed corpus dir ...]
#
# The seed corpora are only read; the inputs the run adds go to a temporary
# directory and are dropped. fuzz/<name>.dict is used where there is one
# (<name>: the fuzzer's name less "_fuzzer"). Any finding (crash,
# sanitizer report, uncaught exception, an input running past -timeout
# seconds or -rss_limit_mb) stops the run with an error and is saved under
# ./<name>-findings/ to replay: `<fuzzer> <name>-findings/crash-...`. The
# whole log goes to ./<name>_fuzz.log; only the final statistics, or the end
# with the report, are printed, so that CTest's limit on test output cannot
# cut a report off.
set -eu
fuzzer=$1
seconds=${2:-60}
shift $(( $# < 2 ? $# : 2 ))
here=$(cd "$(dirname "$0")" && pwd)
name=$(basename "$fuzzer" _fuzzer)
dict=""
[ -f "$here/$name.dict" ] && dict="-dict=$here/$name.dict"
new_inputs=$(mktemp -d)
trap 'rm -rf "$new_inputs"' EXIT
mkdir -p "$name-findings"
# shellcheck disable=SC2086 # $dict is one option or none
if "$fuzzer" -seed=1 -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 $dict \
  -artifact_prefix="$name-findings/" -print_final_stats=1 "$new_inputs" "$@" > "${name}_fuzz.log" 2>&1; then
  grep -E '^(Done |stat::)' "${name}_fuzz.log"
else
  status=$?
  tail -n 80 "${name}_fuzz.log"
  echo "$(basename "$fuzzer") found a problem (exit $status); whole log: $(pwd)/${name}_fuzz.log"
  exit "$status"
fi
