#!/usr/bin/env bash
# Builds the Debian package with CPack (dependencies from dpkg-shlibdeps) and checks it with
# lintian: no error allowed. Prints the package's name, size and dependencies.
# Usage: package_test.sh BUILD_DIR WORK_DIR
set -euo pipefail
build="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"
trap 'rm -rf "$work"' EXIT
(cd "$work" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work" >cpack.log 2>&1) ||
  { tail -30 "$work/cpack.log" >&2; echo "FAIL: cpack -G DEB" >&2; exit 1; }
deb="$(ls "$work"/*.deb)"
echo "package: $(basename "$deb"), $(du -h "$deb" | cut -f1)"
dpkg-deb --field "$deb" Depends
dpkg-deb --field "$deb" Depends >"$work/depends.txt"
grep -q "libyaml-cpp" "$work/depends.txt" || { echo "FAIL: no shlibdeps dependencies" >&2; exit 1; }
dpkg-deb --contents "$deb" >"$work/contents.txt"
grep -q "usr/share/ctsfleet/config/fleet.yaml" "$work/contents.txt" || { echo "FAIL: configs missing" >&2; exit 1; }
# What find_package(ctsfleet) needs beyond the package: yaml-cpp's CMake files.
grep -q "libyaml-cpp-dev" "$work/depends.txt" || { echo "FAIL: Depends lacks libyaml-cpp-dev (the CMake package finds yaml-cpp)" >&2; exit 1; }
multiarch="$(dpkg-architecture -qDEB_HOST_MULTIARCH)"
grep -q "usr/lib/$multiarch/libplanner_core.a" "$work/contents.txt" ||
  { echo "FAIL: static libraries not in usr/lib/$multiarch" >&2; grep "\.a$" "$work/contents.txt" >&2; exit 1; }
for page in ctsfleet-ca ctsfleet-plot ctsfleet-solve; do
  grep -q "usr/share/man/man1/$page.1.gz" "$work/contents.txt" || { echo "FAIL: no man page for $page" >&2; exit 1; }
done
# lintian leaves its ELF caches (mldbm-elf-*) in TMPDIR: give it one that goes with $work.
mkdir -p "$work/tmp"
TMPDIR="$work/tmp" lintian --fail-on error --no-tag-display-limit "$deb" | tee "$work/lintian.log" ||
  { echo "FAIL: lintian reports errors" >&2; exit 1; }
echo "lintian: $(grep -c '^E:' "$work/lintian.log" || true) errors, $(grep -c '^W:' "$work/lintian.log" || true) warnings"
