#!/usr/bin/env bash
# Builds the libFuzzer target for the scene parser (fuzz/fuzz_scene.cpp) with ASan and UBSan and
# runs it for a bounded time (docs/fuzzing.md). Not part of the default build or CI.
#
# Usage: tools/fuzz_scene.sh [SECONDS]     (default 600; extra libFuzzer flags via FUZZ_FLAGS;
#        FUZZ_TOML=shared|header chooses how toml++ is linked, see below)
#   Needs clang++ and the libFuzzer runtime (Debian: apt-get install clang libclang-rt-14-dev).
#   Everything it writes goes under fuzz/build/ (ignored by git): the binary, the growing corpus
#   (fuzz/build/corpus; fuzz/corpus holds the checked-in seeds and is only read) and any crash
#   input (fuzz/build/artifacts/). Exits non-zero when the fuzzer finds a crash, a sanitizer
#   report, a timeout or an out-of-memory.
# Reproduce a finding: fuzz/build/fuzz_scene fuzz/build/artifacts/crash-...
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
seconds=${1:-600}
[[ "$seconds" =~ ^[0-9]+$ && "$seconds" -ge 1 ]] || { echo "usage: $0 [SECONDS]" >&2; exit 2; }
cxx=${CXX_FUZZ:-clang++}
build=$root/fuzz/build
bin=$build/fuzz_scene
mkdir -p "$build/generated" "$build/corpus" "$build/artifacts"

# The embedded default scene that src/scene/scene.cpp includes (what CMake's configure_file makes).
header=$build/generated/default_scene.hpp
{
  sed -n '1,4p' "$root/src/scene/default_scene.hpp.in"
  printf 'inline constexpr std::string_view default_scene_toml = R"eulervop_scene('
  cat "$root/data/scenes/paper-fig1.toml"
  printf ')eulervop_scene";\n'
  sed -n '6,$p' "$root/src/scene/default_scene.hpp.in"
} >"$header.tmp"
cmp -s "$header.tmp" "$header" && rm "$header.tmp" || mv "$header.tmp" "$header"

# clang has __float128 on x86-64 but not GCC's quadmath.h (Boost's float128 includes it): expose
# just that header from the GCC installation, not GCC's whole include directory.
gcc_include=$(gcc -print-file-name=include)
mkdir -p "$build/quadmath-include"
for h in quadmath.h quadmath_weak.h; do
  [[ -f "$gcc_include/$h" ]] || { echo "$h not found in $gcc_include (install gcc / libquadmath)" >&2; exit 2; }
  ln -sf "$gcc_include/$h" "$build/quadmath-include/$h"
done

sources=("$root/fuzz/fuzz_scene.cpp" "$root"/src/scene/*.cpp)
deps=("${sources[@]}" "$root"/src/scene/*.hpp "$root"/include/eulervop/scene/*.hpp "$root"/include/eulervop/model/*.hpp
      "$root"/include/eulervop/*.hpp "$header" "$0")
rebuild=0
[[ -x "$bin" ]] || rebuild=1
toml_mode=${FUZZ_TOML:-shared}
[[ "$toml_mode" == shared || "$toml_mode" == header ]] || { echo "FUZZ_TOML must be shared or header" >&2; exit 2; }
stamp=$build/config-$toml_mode-asserts${FUZZ_TOML_ASSERTS:-0}
[[ -f "$stamp" ]] || rebuild=1
for f in "${deps[@]}"; do [[ "$f" -nt "$bin" ]] && rebuild=1; done
if ((rebuild)); then
  echo "building $bin" >&2
  # toml++: by default the shipped shared library is linked, as in the main build, so the run
  # tests what ships; sanitizers and coverage then cover our code and the toml++ inline headers.
  # FUZZ_TOML=header compiles toml++ 3.3.0 header-only and instrumented instead: that finds
  # known upstream bugs within seconds (docs/fuzzing.md), so it is for looking at toml++ itself.
  # Its debug assertions are then off (FUZZ_TOML_ASSERTS=1 keeps them), as in the shipped
  # library: "[[[1]]]" trips one although it ends in a normal parse_error (upstream #301).
  # NDEBUG is not used: with clang it would turn them into __builtin_assume (UB on those inputs).
  if [[ "$toml_mode" == header ]]; then
    toml_flags=(-DTOML_HEADER_ONLY=1 -DTOML_EXCEPTIONS=1)
    [[ "${FUZZ_TOML_ASSERTS:-0}" == 1 ]] || toml_flags+=(-D'TOML_ASSERT(expr)=static_cast<void>(0)')
    toml_libs=()
  else
    toml_flags=(-DTOML_HEADER_ONLY=0 -DTOML_SHARED_LIB=1 -DTOML_EXCEPTIONS=1)
    toml_libs=(-ltomlplusplus)
  fi
  "$cxx" -std=gnu++20 -O1 -g -fno-omit-frame-pointer \
    -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all \
    -D_GLIBCXX_ASSERTIONS "${toml_flags[@]}" \
    -I"$root/include" -I"$build/generated" -isystem "$build/quadmath-include" \
    "${sources[@]}" -o "$bin.tmp" \
    "${toml_libs[@]}" -lfmt -lmpfr -lgmp -L"$(dirname "$(gcc -print-file-name=libquadmath.so)")" -lquadmath
  mv "$bin.tmp" "$bin"
  rm -f "$build"/config-* && touch "$stamp"
fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
echo "fuzzing for ${seconds}s: $bin" >&2
set +e
# shellcheck disable=SC2086
"$bin" -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
  -dict="$root/fuzz/toml.dict" -artifact_prefix="$build/artifacts/" -print_final_stats=1 \
  ${FUZZ_FLAGS:-} "$build/corpus" "$root/fuzz/corpus"
status=$?
set -e
if ((status != 0)); then
  echo "fuzz_scene: FAILED (exit $status); inputs in $build/artifacts/" >&2
  exit 1
fi
echo "fuzz_scene: no crash in ${seconds}s" >&2
