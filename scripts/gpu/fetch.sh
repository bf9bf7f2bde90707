#!/usr/bin/env bash
# The half of the GPU bring-up that needs a network: on a Debian 12 machine where
# scripts/setup.sh has built cmc, download the Debian packages that a build of cmc needs and
# unpack them into one folder, to be copied to a GPU machine that has neither our packages nor
# a network (seen: Ubuntu 24.04, g++ 13, CMake 4, CUDA 13). There, scripts/gpu/build.sh builds
# and tests from that folder alone.
#
#   scripts/gpu/fetch.sh [BUNDLE]        (default: gpu-bundle; ignored by git)
#
# BUNDLE/debs/      the .deb files, as apt-get download gives them
# BUNDLE/prefix/    each unpacked with dpkg -x (Debian's layout under prefix/usr)
# BUNDLE/packages.txt  name, version and sha256 of every .deb, for the record
#
# Which packages: the -dev packages that CMakeLists.txt finds (FFTW, GSL, HDF5, toml++,
# GoogleTest, Google Benchmark), and every package that holds a shared library that this
# machine's build/cmc and build/cmc_bench load (ldd), except the C and C++ runtimes
# (libc6, libgcc-s1, libstdc++6, libgomp1) that the GPU machine's own compiler brings. The
# second list is computed here from ldd, not written down, so that it follows Debian's
# dependencies (HDF5 pulls in libcurl and its TLS and Kerberos libraries).
set -euo pipefail
cd "$(dirname "$0")/../.."
bundle=${1:-gpu-bundle}

die() { echo "scripts/gpu/fetch.sh: $*" >&2; exit 1; }
command -v apt-get >/dev/null && command -v dpkg >/dev/null || die "needs Debian's apt-get and dpkg (run it on the Debian machine that builds cmc)"
for b in build/cmc build/cmc_bench; do
  [ -x "$b" ] || die "$b is missing: run scripts/setup.sh first (its ldd decides which libraries to carry)"
done

dev=(libfftw3-dev libgsl-dev libhdf5-dev libtomlplusplus-dev libgtest-dev libbenchmark-dev)
runtime=()
while read -r lib; do
  # dpkg knows a library by the path its package installed: the resolved file, or the link.
  pkg=$(dpkg -S "$(readlink -f "$lib")" 2>/dev/null | head -1 | cut -d: -f1 || true)
  [ -n "$pkg" ] || pkg=$(dpkg -S "$lib" 2>/dev/null | head -1 | cut -d: -f1 || true)
  [ -n "$pkg" ] || die "no Debian package holds $lib (ldd of build/cmc): is it a library built by hand?"
  case "$pkg" in libc6|libgcc-s1|libstdc++6|libgomp1) ;; *) runtime+=("$pkg") ;; esac
done < <(ldd build/cmc build/cmc_bench | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | sort -u)
mapfile -t all < <(printf '%s\n' "${dev[@]}" "${runtime[@]}" | sort -u)

mkdir -p "$bundle/debs" "$bundle/prefix"
echo "scripts/gpu/fetch.sh: downloading ${#all[@]} packages into $bundle/debs" >&2
(cd "$bundle/debs" && apt-get download -q "${all[@]}" 2>&1 | grep -v "^W: Download is performed unsandboxed" >&2) ||
  die "apt-get download failed (network? package names above)"
tmp=$(mktemp "$bundle/.packages.XXXXXX")
for deb in "$bundle"/debs/*.deb; do
  dpkg -x "$deb" "$bundle/prefix"
  printf '%s %s %s\n' "$(dpkg-deb -f "$deb" Package)" "$(dpkg-deb -f "$deb" Version)" \
    "$(sha256sum "$deb" | cut -d' ' -f1)" >>"$tmp"
done
sort -o "$tmp" "$tmp" && mv "$tmp" "$bundle/packages.txt"
du -sh "$bundle" | awk -v n="$(wc -l <"$bundle/packages.txt")" \
  '{print "scripts/gpu/fetch.sh: " n " packages, " $1 " in " $2 "; copy it with the checkout to the GPU machine and run scripts/gpu/build.sh " $2}' >&2
