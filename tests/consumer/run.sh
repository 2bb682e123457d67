#!/usr/bin/env bash
# gonio as an outsider uses it (issue 10): install the build BUILD_DIR to a temporary
# prefix, then
#   1. check the installed tool: `gonio --version`, and no source- or build-tree path in it;
#   2. configure tests/consumer/ with find_package(gonio 0.2 COMPONENTS core) alone and
#      check that no renderer package was searched for;
#   3. configure, build and run it with COMPONENTS core render (core only when gonio was
#      built without the renderer);
#   4. compile and run pkgconfig_core.cpp with `pkg-config --cflags --libs gonio` alone.
# Usage: run.sh BUILD_DIR SOURCE_DIR CXX render|core. Cleans up after itself.
set -euo pipefail
build_dir="$1" source_dir="$2" cxx="$3" components="$4"
here="$(cd "$(dirname "$0")" && pwd)"

tmp="$(mktemp -d "${TMPDIR:-/tmp}/gonio-consumer.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
fail() { echo "consumer: $*" >&2; exit 1; }

cmake --install "$build_dir" --prefix "$prefix" >"$tmp/install.log" 2>&1 ||
  { cat "$tmp/install.log" >&2; fail "cmake --install $build_dir failed"; }

# 1. The installed tool.
version="$("$prefix/bin/gonio" --version)" || fail "installed gonio --version exited $?"
expected="gonio $(sed -n 's/^#define GONIO_VERSION_STRING "\(.*\)"$/\1/p' "$prefix/include/gonio/version.h")"
[ "$version" = "$expected" ] || fail "installed gonio --version printed '$version', expected '$expected'"
for f in "$prefix"/bin/gonio "$prefix"/lib*/libgonio* "$prefix"/lib*/*/libgonio*; do
  [ -f "$f" ] || continue
  for tree in "$source_dir" "$build_dir"; do
    if strings "$f" | grep -qF "$tree"; then fail "$f contains the path $tree"; fi
  done
done
if grep -rqF -e "$source_dir" -e "$build_dir" "$prefix"/lib*/cmake "$prefix"/lib*/pkgconfig 2>/dev/null; then
  fail "an installed CMake or pkg-config file names the source or build tree"
fi
echo "consumer: installed $version"

common=(-DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$prefix")

# 2. The core component alone searches for no renderer package.
cmake -S "$here" -B "$tmp/core" "${common[@]}" -DCONSUMER_RENDER=OFF >"$tmp/core.log" 2>&1 ||
  { cat "$tmp/core.log" >&2; fail "configuring tests/consumer with COMPONENTS core failed"; }
if grep -E "^(embree|TBB|OpenEXR|PNG|tinyobjloader)_(DIR|LIBRARY|INCLUDE_DIR)[:=]" "$tmp/core/CMakeCache.txt"; then
  fail "find_package(gonio COMPONENTS core) searched for a renderer package"
fi

# 3. find_package(gonio 0.2 REQUIRED COMPONENTS core render): build and run.
render=ON
[ "$components" = render ] || render=OFF
cmake -S "$here" -B "$tmp/full" "${common[@]}" -DCONSUMER_RENDER="$render" >"$tmp/full.log" 2>&1 ||
  { cat "$tmp/full.log" >&2; fail "configuring tests/consumer failed"; }
cmake --build "$tmp/full" -j2 >"$tmp/build.log" 2>&1 ||
  { cat "$tmp/build.log" >&2; fail "building tests/consumer failed"; }
"$tmp/full/consumer_core"
if [ "$render" = ON ]; then "$tmp/full/consumer_render"; fi

# 4. pkg-config: the flags are all a compiler needs (plus the language standard).
libdir="$(dirname "$(find "$prefix" -name gonio.pc -path '*/pkgconfig/*' | head -n 1)")"
[ -d "$libdir" ] || fail "no gonio.pc installed"
export PKG_CONFIG_PATH="$libdir${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
flags="$(pkg-config --cflags --libs gonio)" || fail "pkg-config --cflags --libs gonio failed"
# shellcheck disable=SC2086  # the flags are words
"$cxx" -std=c++20 -O1 "$here/pkgconfig_core.cpp" -o "$tmp/pkgconfig_core" $flags ||
  fail "compiling with \`pkg-config --cflags --libs gonio\` ($flags) failed"
LD_LIBRARY_PATH="$(dirname "$libdir")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$tmp/pkgconfig_core"
if [ "$render" = ON ]; then
  pkg-config --exists gonio-render || fail "gonio-render.pc is not usable: $(pkg-config --print-errors gonio-render 2>&1)"
fi
echo "consumer: passed"
