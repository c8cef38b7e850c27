#!/usr/bin/env bash
# Robustness run (docs/SECURITY.md): schemathesis from PyPI against the
# running service's /openapi.json, with access control on and an admin token,
# checking that no generated request gives a 5xx and that every answer
# matches the document (status codes, media types, schemas).
#
#   tests/robustness/schemathesis.sh [MAX_EXAMPLES]   (default 60 per operation)
#
# Builds and starts `kuka-bridge run --simulate --require-auth` (release) on a
# free port in a temporary data folder; installs schemathesis into
# ~/.cache/kuka-bridge/st-venv on first use. Not part of CI.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
examples="${1:-60}"
venv="${KB_ST_VENV:-$HOME/.cache/kuka-bridge/st-venv}"
if [ ! -x "$venv/bin/schemathesis" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q schemathesis
fi
cargo build --release -q --manifest-path "$here/Cargo.toml" -p kuka-bridge
exe="${CARGO_TARGET_DIR:-$here/target}/release/kuka-bridge"
tmp="$(mktemp -d)"
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
"$exe" run --simulate --require-auth --time-scale 0 --listen "127.0.0.1:$port" --data-dir "$tmp/data" \
    >"$tmp/service.out" 2>"$tmp/service.err" &
pid=$!
trap 'kill $pid 2>/dev/null; wait $pid 2>/dev/null; echo "service logs: $tmp"' EXIT
for _ in $(seq 100); do
    curl -fsS "http://127.0.0.1:$port/health" >/dev/null 2>&1 && break
    sleep 0.1
done
admin=$(grep '^kb_' "$tmp/data/initial-admin-token.txt")
# Excluded: the event stream (never ends, so no answer to check) and token
# revocation (a generated name could revoke the admin token mid-run).
"$venv/bin/schemathesis" run "http://127.0.0.1:$port/openapi.json" \
    --header "Authorization: Bearer $admin" \
    --checks not_a_server_error,status_code_conformance,content_type_conformance,response_schema_conformance \
    --exclude-path /api/v1/events \
    --exclude-path-regex '^/api/v1/tokens/' \
    --max-examples "$examples" --workers 2 --request-timeout 30 \
    --phases examples,coverage,fuzzing \
    --report junit --report-dir "$tmp/report" \
    --no-color | tee "$tmp/schemathesis.out"
