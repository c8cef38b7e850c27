#!/usr/bin/env bash
# Builds the kuka-bridge MSI on Linux:
#   1. cross-compiles the release exe (x86_64-pc-windows-gnu),
#   2. lists README/LICENSE, docs/*.md, krl/PROTOCOL.md and krl/KRC/** with
#      wixl-heat into a generated fragment,
#   3. runs `wixl -a x64` on installer/kuka-bridge.wxs + that fragment.
# Prints the MSI's path as its last line of stdout.
#
# Usage: installer/build-msi.sh [--exe PATH] [--out FILE.msi] [--version X.Y.Z]
#   --exe PATH   use an already built kuka-bridge.exe (skips cargo)
#   --version V  MSI ProductVersion instead of Cargo.toml's (tests of the
#                major upgrade build a second MSI with a higher one)
#   --out FILE   where to write the MSI
#                (default $CARGO_TARGET_DIR/kuka-bridge-<version>-x64.msi)
# Needs: cargo with the x86_64-pc-windows-gnu target, gcc-mingw-w64-x86-64,
# wixl and msitools (Debian/Ubuntu: apt-get install wixl msitools
# gcc-mingw-w64-x86-64). Honours CARGO_TARGET_DIR and CARGO_BUILD_JOBS.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
target_dir="${CARGO_TARGET_DIR:-$root/target}"
triple=x86_64-pc-windows-gnu
exe=""
out=""
version_override=""

while [ $# -gt 0 ]; do
    case "$1" in
        --exe) exe="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        --version) version_override="$2"; shift 2 ;;
        -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
        *) echo "build-msi.sh: unknown argument $1" >&2; exit 2 ;;
    esac
done

for tool in wixl wixl-heat; do
    command -v "$tool" >/dev/null || {
        echo "build-msi.sh: $tool not found (apt-get install wixl msitools)" >&2
        exit 1
    }
done

# The product version: [workspace.package] version in the root Cargo.toml
# (the service crate has version.workspace = true).
version="$(awk '
    /^\[/ { in_ws = ($0 == "[workspace.package]") }
    in_ws && /^version[ \t]*=/ { gsub(/.*=[ \t]*"|".*/, ""); print; exit }
' "$root/Cargo.toml")"
case "$version" in
    [0-9]*.[0-9]*.[0-9]*) ;;
    *) echo "build-msi.sh: cannot read the version from $root/Cargo.toml" >&2; exit 1 ;;
esac
# MSI ProductVersion is numeric major.minor.build: drop any -pre/+build part.
msi_version="${version%%[-+]*}"
if [ -n "$version_override" ]; then
    version="$version_override"
    msi_version="$version_override"
fi

if [ -z "$exe" ]; then
    echo "== cross-compiling kuka-bridge.exe $version (release, $triple)" >&2
    (cd "$root" && cargo build --release --target "$triple" -p kuka-bridge >&2)
    exe="$target_dir/$triple/release/kuka-bridge.exe"
fi
[ -f "$exe" ] || { echo "build-msi.sh: $exe not found" >&2; exit 1; }
exe="$(cd "$(dirname "$exe")" && pwd)/$(basename "$exe")"

[ -n "$out" ] || out="$target_dir/kuka-bridge-$version-x64.msi"
mkdir -p "$(dirname "$out")"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# The release build carries line tables (≈ 200 MB); the MSI ships the exe
# without debug information and symbols (≈ 40 MB). They go to a separate
# artifact beside the MSI, for crash analysis (gdb or addr2line with the
# .debug file next to the exe; the exe names it in .gnu_debuglink).
debug_file="$(dirname "$out")/kuka-bridge-$version.exe.debug"
objcopy_bin="${OBJCOPY:-x86_64-w64-mingw32-objcopy}"
if command -v "$objcopy_bin" >/dev/null; then
    "$objcopy_bin" --only-keep-debug "$exe" "$debug_file"
    "$objcopy_bin" --strip-all --add-gnu-debuglink="$debug_file" "$exe" "$work/kuka-bridge.exe"
    echo "== kuka-bridge.exe $(du -m "$work/kuka-bridge.exe" | cut -f1) MB shipped; symbols and line tables in $debug_file" >&2
else
    echo "build-msi.sh: $objcopy_bin not found: the MSI ships the exe with its debug information" >&2
    # wixl resolves File/@Source relative to the current directory and cannot
    # take absolute paths, so it runs in a staging folder of symlinks.
    ln -s "$exe" "$work/kuka-bridge.exe"
fi
ln -s "$root/docs" "$work/docs"
ln -s "$root/krl" "$work/krl"

# Generated file list. wixl-heat derives Directory/Component/File ids from
# the paths and Guid="*" makes wixl derive component GUIDs from the key
# path, so the same tree gives the same MSI tables on every build.
heat() { # group directory-ref < file list
    wixl-heat --win64 --component-group "$1" --directory-ref "$2" \
        --var var.SrcDir -p ""
}
(
    cd "$root"
    for f in README.md LICENSE* COPYING*; do
        if [ -f "$f" ]; then ln -s "$root/$f" "$work/$f" && echo "$f"; fi
    done | heat RootFiles INSTALLDIR >"$work/files-root.wxs"
    find docs -maxdepth 1 -type f -name '*.md' | LC_ALL=C sort |
        heat Docs INSTALLDIR >"$work/files-docs.wxs"
    { echo krl/PROTOCOL.md; find krl/KRC -type f | LC_ALL=C sort; } |
        heat Krl INSTALLDIR >"$work/files-krl.wxs"
)
cp "$here/kuka-bridge.wxs" "$work/"

echo "== wixl -a x64 (version $msi_version) -> $out" >&2
(
    cd "$work"
    wixl -a x64 \
        -D Version="$msi_version" \
        -D Win64=yes \
        -D SrcDir=. \
        -o product.msi \
        kuka-bridge.wxs files-root.wxs files-docs.wxs files-krl.wxs
)
mv "$work/product.msi" "$out"

echo "$out"
