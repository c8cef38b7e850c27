#!/usr/bin/env bash
# Refreshes the vendored front-end libraries of the dashboard from npm
# (pinned versions; SHA256SUMS records what was taken). Only
# needed when a version changes: the Rust build embeds the files below and
# never needs Node or the network.
#
#   service/dashboard/vendor.sh      (needs npm and tar)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
out="$here/vendor"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
THREE=0.187.0
(cd "$tmp" && npm pack --silent "three@$THREE" >/dev/null)
tar -xzf "$tmp/three-$THREE.tgz" -C "$tmp" package/build/three.module.js package/build/three.core.js \
    package/examples/jsm/controls/OrbitControls.js package/LICENSE
mkdir -p "$tmp/three" && mv "$tmp/package" "$tmp/three/"
mkdir -p "$out"
cp "$tmp/three/package/build/three.module.js" "$tmp/three/package/build/three.core.js" "$out/"
# OrbitControls imports the bare name 'three'; point it at the file (no
# import map needed).
sed "s#from 'three'#from './three.module.js'#" \
    "$tmp/three/package/examples/jsm/controls/OrbitControls.js" >"$out/OrbitControls.js"
{
    echo "# Vendored front-end libraries"
    echo
    echo "Fetched by \`service/dashboard/vendor.sh\` from npm; embedded in the kuka-bridge binary."
    echo
    echo "| package | version | files | licence |"
    echo "|---|---|---|---|"
    echo "| three | $THREE | three.module.js, three.core.js, OrbitControls.js (import path rewritten) | MIT |"
    echo
    echo "## three $THREE"
    echo
    echo '```'
    cat "$tmp/three/package/LICENSE"
    echo '```'
} >"$out/LICENSES.md"
(cd "$out" && sha256sum three.module.js three.core.js OrbitControls.js >SHA256SUMS)
echo "vendored into $out"
