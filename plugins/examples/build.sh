#!/usr/bin/env bash
# Builds the example and fixture plugins into OUT_DIR:
#   draw-circle.wasm, draw-circle-0.2.0.wasm, draw-smiley.wasm, pick-and-place.wasm,
#   misbehave.wasm, bad-describe.wasm, other-world.wasm, old-contract.wasm
#   and, with --python, py-square.wasm.
#
# usage: plugins/examples/build.sh OUT_DIR [--python]
#
# Environment:
#   CARGO_TARGET_DIR  cargo's target folder (default: plugins/examples/target)
#   CARGO_BUILD_JOBS  parallel jobs, as for cargo
#   KB_PY_VENV        venv holding componentize-py (default: ~/.cache/kuka-bridge/venv;
#                     created, and componentize-py==0.25.1 pip-installed, when missing)
#
# Needs Rust with the wasm32-wasip2 target (rustup installs it from the repository's
# rust-toolchain.toml) and, for --python, python3 with venv. Running it again when
# nothing changed takes a second: cargo is incremental, files that did not change
# are not copied, and the Python component is rebuilt only when app.py or the WIT is
# newer than it.
set -euo pipefail

usage() { echo "usage: $0 OUT_DIR [--python]" >&2; exit 2; }

out="" python=0
for arg in "$@"; do
    case "$arg" in
        --python) python=1 ;;
        -h|--help) usage ;;
        -*) echo "unknown option: $arg" >&2; usage ;;
        *) [[ -z "$out" ]] || usage; out="$arg" ;;
    esac
done
[[ -n "$out" ]] || usage

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
wit="$here/../wit"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$here/target}"
mkdir -p "$out"
out="$(cd "$out" && pwd)"

# install SRC NAME: copies SRC to OUT_DIR/NAME unless it is already identical.
install() {
    local dst="$out/$2"
    cmp -s "$1" "$dst" 2>/dev/null || cp "$1" "$dst"
    printf '%-45s %10s bytes\n' "$dst" "$(wc -c < "$dst" | tr -d ' ')"
}

cargo_wasm() {
    cargo build --quiet --release --target wasm32-wasip2 --manifest-path "$here/Cargo.toml" "$@"
}

# Every Rust guest, then draw-circle again as version 0.2.0 in a target folder
# of its own (so neither build invalidates the other).
cargo_wasm --workspace
cargo_wasm -p draw-circle --features next-version --target-dir "$CARGO_TARGET_DIR/next-version"

wasm="$CARGO_TARGET_DIR/wasm32-wasip2/release"
install "$wasm/draw_circle.wasm" draw-circle.wasm
install "$CARGO_TARGET_DIR/next-version/wasm32-wasip2/release/draw_circle.wasm" draw-circle-0.2.0.wasm
install "$wasm/draw_smiley.wasm" draw-smiley.wasm
install "$wasm/pick_and_place.wasm" pick-and-place.wasm
install "$wasm/misbehave.wasm" misbehave.wasm
install "$wasm/bad_describe.wasm" bad-describe.wasm
install "$wasm/other_world.wasm" other-world.wasm
install "$wasm/old_contract.wasm" old-contract.wasm

if (( python )); then
    venv="${KB_PY_VENV:-$HOME/.cache/kuka-bridge/venv}"
    [[ -d "$venv" ]] || python3 -m venv "$venv"
    bin="$venv/bin"
    [[ -d "$bin" ]] || bin="$venv/Scripts"   # a venv made by Windows' Python
    cpy="$bin/componentize-py"
    if ! "$cpy" --version 2>/dev/null | grep -q ' 0\.25\.1$'; then
        "$bin/python" -m pip install --quiet --disable-pip-version-check 'componentize-py==0.25.1'
    fi

    app="$here/python/draw-square"
    target="$out/py-square.wasm"
    # Rebuild only when app.py or a WIT file is newer than the component.
    if [[ ! -f "$target" ]] || [[ -n "$(find "$app/app.py" "$wit" -newer "$target" -print -quit)" ]]; then
        tmp="$(mktemp -d)"
        trap 'rm -rf "$tmp"' EXIT
        # componentize-py runs app.py, writing __pycache__ next to it: build a copy.
        cp "$app/app.py" "$tmp/"
        (cd "$tmp" && "$cpy" -d "$wit" -w bridge-plugin componentize app -o py-square.wasm >/dev/null)
        mv "$tmp/py-square.wasm" "$target"
    fi
    install "$target" py-square.wasm
fi
