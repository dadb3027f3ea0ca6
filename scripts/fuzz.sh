#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, AddressSanitizer + UBSan, assertions on)
# in build-fuzz/ and runs each one for FUZZ_SECONDS (default 60), one at a time.
# Prints per target the executions and the crashes found; crash, timeout and
# leak inputs go to fuzz-out/<target>/, the growing corpus to fuzz-out/corpus/.
#   FUZZ_SECONDS=300 bash scripts/fuzz.sh            every target
#   bash scripts/fuzz.sh fuzz_ply fuzz_fill          only these
# Replay one input: build-fuzz/fuzz/fuzz_ply fuzz-out/fuzz_ply/crash-...
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${FUZZ_SECONDS:-60}
timeout_per_input=${FUZZ_TIMEOUT:-10}
rss_limit_mb=${FUZZ_RSS_LIMIT_MB:-2048}
build_dir=build-fuzz
out_dir=fuzz-out
targets=("$@")
((${#targets[@]})) || targets=(fuzz_obj fuzz_ply fuzz_off fuzz_stl fuzz_fill)

# clang with libFuzzer and OpenMP runtimes: a probe that links a fuzz target.
can_build_fuzzers() {
  command -v clang++ >/dev/null &&
    echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' |
    clang++ -x c++ -fsanitize=fuzzer,address -fopenmp - -o /dev/null 2>/dev/null
}
if ! can_build_fuzzers; then
  echo "fuzz: installing clang and its fuzzer and OpenMP runtimes"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
    clang libclang-rt-dev libomp-dev
fi
# The library's dependencies and the build, through setup.sh: Debug flags plus
# -O2, so assertions (Eigen's index checks, CGAL's) stay on.
FOLDFILL_BUILD_DIR="$build_dir" FOLDFILL_CMAKE_ARGS="-DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O2 -DFOLDFILL_FUZZ=ON -DFOLDFILL_SANITIZE=ON \
  -DFOLDFILL_BUILD_TESTS=OFF -DFOLDFILL_BUILD_BENCHMARKS=OFF -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE" \
  bash scripts/setup.sh

seeds="$build_dir/seeds"
rm -rf "$seeds" && mkdir -p "$seeds"
"$build_dir/fuzz/fuzz_make_seeds" "$seeds"

# The seed files and the dictionary of one target.
seed_pattern() {
  case $1 in
    fuzz_fill) echo "*.obj" ;;
    *) echo "*.${1#fuzz_}" ;;
  esac
}
dictionary() {
  case $1 in
    fuzz_fill) echo fuzz/obj.dict ;;
    *) echo "fuzz/${1#fuzz_}.dict" ;;
  esac
}

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export OMP_NUM_THREADS=1

summary=()
failed=0
for target in "${targets[@]}"; do
  corpus="$out_dir/corpus/$target"
  artifacts="$out_dir/$target"
  rm -rf "$artifacts"  # findings of an earlier run: keep them as tests/data/fuzz files
  mkdir -p "$corpus" "$artifacts"
  find "$seeds" -name "$(seed_pattern "$target")" -exec cp {} "$corpus/" \;
  find tests/data/fuzz -name "$(seed_pattern "$target")" -exec cp {} "$corpus/" \; 2>/dev/null || true
  log="$out_dir/$target.log"
  echo "fuzz: $target for ${seconds}s (log $log)"
  # -fork keeps going after a finding, so one run reports every crash it hits.
  "$build_dir/fuzz/$target" "$corpus" -dict="$(dictionary "$target")" \
    -max_total_time="$seconds" -timeout="$timeout_per_input" -rss_limit_mb="$rss_limit_mb" \
    -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -artifact_prefix="$artifacts/" >"$log" 2>&1 || true
  # Fork mode's progress lines: "#EXECUTIONS: cov: ... oom/timeout/crash: O/T/C ...".
  executions=$(grep -oE '^#[0-9]+:' "$log" | tail -n 1 | tr -d '#:')
  findings=$(find "$artifacts" -type f | wc -l)
  summary+=("$(printf '%-10s executions %10s   crashing inputs (crash, timeout, leak, OOM) %s' \
    "$target" "${executions:-0}" "$findings")")
  ((findings == 0)) || failed=1
done

echo
printf '%s\n' "${summary[@]}"
((failed == 0)) || echo "fuzz: findings in $out_dir/<target>/ (replay: $build_dir/fuzz/<target> FILE)"
exit "$failed"
