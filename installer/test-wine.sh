#!/usr/bin/env bash
# installer/test-wine.sh: the MSI's end-to-end proof on Linux, under Wine.
#
# In a private, throw-away WINEPREFIX: builds the ProcessPrng stand-in DLL
# (installer/wine/processprng.c; Wine 8.0 needs it), builds the MSI with
# installer/build-msi.sh (or takes one), installs it with msiexec, checks
# the service runs and the REST API answers /health and a simulated motion,
# restarts it after a config change, stops/starts it through the service
# manager (sc, net and `kuka-bridge service ...`), kills the process,
# checks the failure exit code the service manager records, checks the
# Event Log text (Wine prints ReportEventW with WINEDEBUG=+eventlog),
# uninstalls and checks nothing is left.
#
# Usage: installer/test-wine.sh [--msi FILE.msi | --exe kuka-bridge.exe] [--keep]
#   --msi FILE   test this MSI (skips the build)
#   --exe FILE   build the MSI around this exe (skips cargo)
#   --keep       keep the temp dir (prefix, logs) for debugging
# Environment: KB_WINE_TEST_TIMEOUT (seconds, default 900) bounds the run.
# Needs: wine (wine64), wixl + msitools, gcc-mingw-w64-x86-64, curl, and
# what build-msi.sh needs. Prints PASS/FAIL/SKIP per step, timings per
# phase, and ends with "N passed, M failed"; exits non-zero on any failure.
set -uo pipefail

# Hard overall bound: rerun this script under timeout(1). On expiry the inner
# run gets SIGTERM and its EXIT trap still stops the wineserver.
if [ -z "${KB_WINE_TEST_INNER:-}" ]; then
    export KB_WINE_TEST_INNER=1
    timeout --kill-after=20 "${KB_WINE_TEST_TIMEOUT:-900}" "$0" "$@"
    rc=$?
    [ $rc -eq 124 ] && echo "test-wine.sh: FAIL: overall timeout (${KB_WINE_TEST_TIMEOUT:-900} s)" >&2
    exit $rc
fi

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
msi=""
exe=""
keep=0
while [ $# -gt 0 ]; do
    case "$1" in
        --msi) msi="$(realpath "$2")"; shift 2 ;;
        --exe) exe="$(realpath "$2")"; shift 2 ;;
        --keep) keep=1; shift ;;
        -h|--help) sed -n '2,22p' "$0"; exit 0 ;;
        *) echo "test-wine.sh: unknown argument $1" >&2; exit 2 ;;
    esac
done

# ---------------------------------------------------------------- reporting
passed=0
failed=0
skipped=0
timings=()
pass() { passed=$((passed + 1)); echo "PASS  $*"; }
fail() { failed=$((failed + 1)); echo "FAIL  $*"; }
skip() { skipped=$((skipped + 1)); echo "SKIP  $*"; }
# check "description" command...: PASS if the command succeeds.
check() {
    local what="$1"; shift
    if "$@"; then pass "$what"; else fail "$what"; fi
}
phase_name=""
phase_start=0
phase() { # phase "name": ends the previous phase, starts timing a new one
    phase_end
    phase_name="$1"
    phase_start=$(date +%s%N)
    echo
    echo "== $phase_name"
}
phase_end() {
    [ -n "$phase_name" ] || return 0
    local ms=$((($(date +%s%N) - phase_start) / 1000000))
    timings+=("$(printf '%7.1f s  %s' "$(echo "$ms" | awk '{print $1/1000}')" "$phase_name")")
    phase_name=""
}
summary() {
    phase_end
    echo
    echo "== timings"
    printf '%s\n' "${timings[@]}"
    echo
    [ "$skipped" = 0 ] || echo "$skipped skipped (Wine limits, see SKIP lines)"
    echo "$passed passed, $failed failed"
}

# ---------------------------------------------------------------- the prefix
tmp="$(mktemp -d "${TMPDIR:-/tmp}/kb-wine-test.XXXXXX")"
logs="$tmp/logs"
mkdir -p "$logs"
export WINEPREFIX="$tmp/prefix"
export WINEARCH=win64
export WINEDLLOVERRIDES="mscoree,mshtml=" # no Mono/Gecko install prompts
export WINEDEBUG=-all                      # quiet tools; services get +eventlog
unset DISPLAY WAYLAND_DISPLAY              # headless, like CI
server_up=0

cleanup() {
    local rc=$?
    if [ "$server_up" = 1 ]; then
        wineserver -k >/dev/null 2>&1 || true
        timeout 30 wineserver -w >/dev/null 2>&1 || true
    fi
    if [ "$keep" = 1 ] || [ "$failed" -gt 0 ]; then
        echo "test-wine.sh: logs and prefix kept in $tmp"
    else
        rm -rf "$tmp"
    fi
    exit $rc
}
trap cleanup EXIT
trap 'failed=$((failed + 1)); echo "FAIL  interrupted (timeout or signal)"; exit 124' TERM INT

# Every Wine call is bounded; CRs are stripped from its output.
W() { timeout "${WT:-120}" wine "$@" 2>>"$logs/wine-stderr.log" | tr -d '\r'; }

# W_once_more OUT CMD...: run CMD under Wine into OUT; once in many runs Wine
# starts a console exe and it prints nothing at all (no stderr either, seen in
# CI for 'service status' and 'token create'): run it once more then, and keep
# the empty try on record.
W_once_more() {
    local out=$1
    shift
    W "$@" >"$out"
    if [ ! -s "$out" ]; then
        echo "(first '$*' printed nothing; ran again)" >>"$logs/wine-stderr.log"
        W "$@" >"$out"
    fi
}
winpath() { local p="${1//\//\\}"; echo "Z:$p"; }
has() { printf '%s' "$1" | grep -q -- "$2"; }
# kuka-bridge.exe processes of this prefix (not of other prefixes on the host)
our_processes() {
    local pid
    for pid in $(pgrep -f 'kuka-bridge\.exe'); do
        tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx "WINEPREFIX=$WINEPREFIX" && echo "$pid"
    done
}
svc_query() { W sc query kuka-bridge; }
svc_field() { # svc_field STATE|WIN32_EXIT_CODE|SERVICE_EXIT_CODE -> value
    svc_query | awk -v f="$1" '$1 == f { print (f == "STATE") ? $4 : $3; exit }'
}
wait_state() { # wait_state RUNNING|STOPPED seconds
    local i
    for ((i = 0; i < $2 * 2; i++)); do
        [ "$(svc_field STATE)" = "$1" ] && return 0
        sleep 0.5
    done
    return 1
}
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
free_port() {
    local p
    while :; do
        p=$((20000 + RANDOM % 40000))
        port_free "$p" && { echo "$p"; return; }
    done
}
health() { # health PORT: the JSON of GET /health, or nothing
    curl -fsS -m 5 "http://127.0.0.1:$1/health" 2>/dev/null
}
wait_health() { # wait_health PORT seconds
    local i
    for ((i = 0; i < $2 * 2; i++)); do
        # up: "ok", or "degraded" (no controller on this machine)
        health "$1" | grep -Eq '"status":"(ok|degraded)"' && return 0
        sleep 0.5
    done
    return 1
}
write_config() { # write_config DIR PORT [broken|auth]
    mkdir -p "$1"
    if [ "${3:-}" = broken ]; then
        printf 'this is = = not TOML\n' >"$1/kuka-bridge.toml"
        return
    fi
    cat >"$1/kuka-bridge.toml" <<EOF
# written by installer/test-wine.sh
[server]
listen = "127.0.0.1:$2"

[simulator]
enabled = true
time_scale = 0.0
EOF
    if [ "${3:-}" = auth ]; then
        printf '\n[auth]\nrequire_on_loopback = true\n' >>"$1/kuka-bridge.toml"
    fi
}

drive_c="$WINEPREFIX/drive_c"
install_dir="$drive_c/Program Files/kuka-bridge"
exe_win='C:\Program Files\kuka-bridge\kuka-bridge.exe'
evl_key='HKLM\SYSTEM\CurrentControlSet\Services\EventLog\Application\kuka-bridge'
# The documented config location, and the one Wine 8 hands a *service* as
# %ProgramData% (its userenv sets ProgramData=C:\users\Public for services,
# while msiexec and consoles see C:\ProgramData).
cfg_dir="$drive_c/ProgramData/kuka-bridge"
wine_svc_cfg_dir="$drive_c/users/Public/kuka-bridge"

# ------------------------------------------------------------------- tools
phase "tools"
missing=""
for t in wine wineserver wineboot wixl msiinfo x86_64-w64-mingw32-gcc curl timeout; do
    command -v "$t" >/dev/null || missing="$missing $t"
done
if [ -n "$missing" ]; then
    fail "tools present (missing:$missing; apt-get install wine64 wine wixl msitools gcc-mingw-w64-x86-64 curl)"
    summary
    exit 1
fi
pass "tools present ($(wine --version 2>/dev/null), wixl $(wixl --version 2>/dev/null))"

# -------------------------------------------------------------------- shim
phase "ProcessPrng stand-in DLL (mingw)"
shim="$tmp/bcryptprimitives.dll"
check "build bcryptprimitives.dll from installer/wine/processprng.c" \
    x86_64-w64-mingw32-gcc -O2 -s -shared -o "$shim" \
    "$here/wine/processprng.c" "$here/wine/processprng.def" -ladvapi32

# --------------------------------------------------------------------- MSI
if [ -z "$msi" ]; then
    phase "MSI build (build-msi.sh${exe:+ --exe})"
    msi="$tmp/kuka-bridge-test.msi"
    if "$here/build-msi.sh" ${exe:+--exe "$exe"} --out "$msi" >"$logs/build-msi.log" 2>&1; then
        pass "build-msi.sh -> $(basename "$msi") ($(du -h "$msi" | cut -f1))"
    else
        fail "build-msi.sh (see below)"
        tail -30 "$logs/build-msi.log"
        summary
        exit 1
    fi
fi

phase "MSI tables (msiinfo)"
msi_has() { msiinfo export "$msi" "$1" 2>/dev/null | tr -d '\r' | grep -qE "$2"; }
check "ServiceInstall: kuka-bridge, auto start, own process, 'service run --config [CommonAppDataFolder]...'" \
    msi_has ServiceInstall $'^KukaBridgeService\tkuka-bridge\tKUKA Bridge\t16\t2\t1\t.*\tservice run --config "\\[CommonAppDataFolder\\]kuka-bridge\\\\kuka-bridge.toml"\t'
check "ServiceControl: start on install, stop both, remove on uninstall, wait" \
    msi_has ServiceControl $'\tkuka-bridge\t163\t\t1\t'
check "Registry: Event Log source, EventMessageFile REG_EXPAND_SZ, TypesSupported 7" \
    bash -c "msiinfo export '$msi' Registry | grep -q 'EventMessageFile	#%%SystemRoot%' &&
             msiinfo export '$msi' Registry | grep -q 'TypesSupported	#7'"
check "CustomAction: deferred, no-impersonate 'service install --from-msi' (3090)" \
    msi_has CustomAction $'^ConfigureService\t3090\tkuka_bridge.exe\tservice install --from-msi'
check "sequence: InstallServices < ConfigureService < StartServices" bash -c "
    msiinfo export '$msi' InstallExecuteSequence | tr -d '\r' | awk -F'\t' '
        \$1==\"InstallServices\"{a=\$3} \$1==\"ConfigureService\"{b=\$3} \$1==\"StartServices\"{c=\$3}
        END{exit !(a<b && b<c)}'"
check "CustomAction: 'service stop --from-msi' and 'service uninstall --from-msi', deferred, no-impersonate, never failing (3154)" bash -c "
    msiinfo export '$msi' CustomAction | tr -d '\r' | grep -q \$'^WaitForServiceExit\t3154\tkuka_bridge.exe\tservice stop --from-msi' &&
    msiinfo export '$msi' CustomAction | tr -d '\r' | grep -q \$'^UnconfigureService\t3154\tkuka_bridge.exe\tservice uninstall --from-msi'"
check "sequence: InstallInitialize < StopServices < WaitForServiceExit < UnconfigureService < RemoveFiles" bash -c "
    msiinfo export '$msi' InstallExecuteSequence | tr -d '\r' | awk -F'\t' '
        {s[\$1]=\$3}
        END{exit !(s[\"InstallInitialize\"]<s[\"StopServices\"] && s[\"StopServices\"]<s[\"WaitForServiceExit\"] &&
                   s[\"WaitForServiceExit\"]<s[\"UnconfigureService\"] && s[\"UnconfigureService\"]<s[\"RemoveFiles\"])}'"
check "Upgrade: fixed UpgradeCode, RemoveExistingProducts after InstallValidate" bash -c "
    msiinfo export '$msi' Upgrade | grep -q '5B0E7E53-8C39-4F0B-9F6E-2E7A4C1D9B21' &&
    msiinfo export '$msi' InstallExecuteSequence | grep -q '^RemoveExistingProducts	.*	1401'"

# ------------------------------------------------------------------ prefix
phase "Wine prefix (wineboot -i)"
if timeout 180 wineboot -i >"$logs/wineboot.log" 2>&1; then
    pass "wineboot -i in $WINEPREFIX"
else
    fail "wineboot -i (see $logs/wineboot.log)"
fi
server_up=1
cp "$shim" "$drive_c/windows/system32/bcryptprimitives.dll"
check "shim installed in system32" test -f "$drive_c/windows/system32/bcryptprimitives.dll"
# Restart the wineserver persistently: services live only as long as it.
# The first Wine process after it starts wineboot -> services.exe, and every
# service inherits that process's stderr and WINEDEBUG: that is where the
# service's ReportEventW text appears.
wineserver -k >/dev/null 2>&1
timeout 30 wineserver -w >/dev/null 2>&1
wineserver -p
WINEDEBUG="fixme-all,+eventlog" timeout 120 wine cmd /c exit 0 \
    >"$logs/services.stdout" 2>"$logs/services-eventlog.log"
check "wineserver -p + services.exe up" \
    bash -c "W() { timeout 60 wine \"\$@\"; }; W sc query eventlog >/dev/null 2>&1"

# ------------------------------------------------------------------ install
phase "msiexec /i"
port_a=$(free_port)
port_w=$(free_port)
while [ "$port_w" = "$port_a" ]; do port_w=$(free_port); done
# Seed the config before installing (the API must not land on a busy :8080).
write_config "$cfg_dir" "$port_a"
write_config "$wine_svc_cfg_dir" "$port_w" # see wine_svc_cfg_dir above
timeout 300 wine msiexec /i "$(winpath "$msi")" /qn /l*v "$(winpath "$logs/msi-install.log")" \
    >"$logs/msiexec-install.out" 2>&1
rc=$?
if [ "$rc" = 0 ]; then pass "msiexec /i exit 0"; else
    fail "msiexec /i exit $rc (see $logs/msi-install.log)"
    grep -a -iE "error|return value 3|halted" "$logs/msi-install.log" | head -10
fi

phase "installed state"
for f in kuka-bridge.exe README.md docs/errors.md docs/CONTROLLER.md krl/PROTOCOL.md \
    krl/KRC/R1/Program/kbridge/kb_submit.src krl/KRC/R1/Program/kbridge/kb_main.dat \
    krl/KRC/R1/System/kb_sps_lines.src; do
    [ -f "$install_dir/$f" ] || { fail "installed: Program Files\\kuka-bridge\\$f"; continue; }
    pass "installed: Program Files\\kuka-bridge\\$f"
done
check "ConfigureService custom action ran (Return value 1)" \
    grep -aq "Action ended .*ConfigureService. Return value 1" "$logs/msi-install.log"
check "custom action made ProgramData\\kuka-bridge\\{logs,plugins}" \
    test -d "$cfg_dir/logs" -a -d "$cfg_dir/plugins"
check "custom action kept the existing config" grep -q "test-wine.sh" "$cfg_dir/kuka-bridge.toml"
check "Event Log source registered (REG_EXPAND_SZ EventCreate.exe, TypesSupported)" bash -c "
    out=\$(timeout 60 wine reg query '$evl_key' 2>/dev/null | tr -d '\r')
    echo \"\$out\" | grep -q 'EventMessageFile.*REG_EXPAND_SZ.*EventCreate.exe' &&
    echo \"\$out\" | grep -q 'TypesSupported.*REG_DWORD.*0x7'"
check "service RUNNING after install (sc query)" wait_state RUNNING 30
svc_query >"$logs/sc-after-install.txt"

# ----------------------------------------------------------------- the API
phase "REST API"
svc_port=""
for ((i = 0; i < 40; i++)); do # whichever config the service read answers
    if health "$port_a" >/dev/null || health "$port_w" >/dev/null; then break; fi
    sleep 0.5
done
if health "$port_a" >/dev/null; then
    pass "service reads C:\\ProgramData\\kuka-bridge\\kuka-bridge.toml (/health on :$port_a)"
    svc_port=$port_a
    svc_cfg_dir=$cfg_dir
elif health "$port_w" >/dev/null; then
    fail "service reads C:\\ProgramData\\kuka-bridge\\kuka-bridge.toml: it read C:\\users\\Public\\kuka-bridge instead (Wine gives services %ProgramData%=C:\\users\\Public; resolve FOLDERID_ProgramData, not the env var); continuing on :$port_w"
    svc_port=$port_w
    svc_cfg_dir=$wine_svc_cfg_dir
else
    fail "/health answers on :$port_a (or :$port_w)"
fi
if [ -n "$svc_port" ]; then
    h=$(health "$svc_port")
    echo "      /health: $h"
    check "/health: status ok, simulated" has "$h" '"simulated":true'
    m=$(curl -fsS -m 30 -X POST -H 'content-type: application/json' \
        -d '{"motions":[{"type":"ptp_axes","axes":{"a1":10}}]}' \
        "http://127.0.0.1:$svc_port/api/v1/motions" 2>&1)
    echo "      motion: ${m:0:160}"
    check "simulated motion done (POST /api/v1/motions, a1=10)" \
        bash -c 'grep -q "\"state\":\"done\"" <<<"$1" && grep -q "\"a1\":10.0" <<<"$1"' _ "$m"

    # A WASM plugin under Windows: wasmtime compiles it, the artifact cache
    # keeps it (checked again after the restart below), its route draws.
    plugin=""
    if "$here/../plugins/examples/build.sh" "$tmp/plugins" >"$logs/plugin-build.log" 2>&1; then
        plugin="$tmp/plugins/draw-circle.wasm"
    fi
    if [ -n "$plugin" ]; then
        p=$(curl -sS -m 60 -X PUT -H 'content-type: application/wasm' --data-binary "@$plugin" \
            "http://127.0.0.1:$svc_port/api/v1/plugins/draw-circle" 2>&1)
        echo "      plugin: ${p:0:160}"
        check "plugin installed (PUT /api/v1/plugins/draw-circle, compiled)" \
            bash -c 'grep -q "\"status\":\"active\"" <<<"$1" && grep -q "\"from_cache\":false" <<<"$1"' _ "$p"
        c=$(curl -sS -m 60 -X POST -H 'content-type: application/json' \
            -d '{"x": 300, "y": 20, "z": 100, "radius": 40}' \
            "http://127.0.0.1:$svc_port/api/v1/plugins/draw-circle/circle" 2>&1)
        echo "      circle: ${c:0:160}"
        check "plugin route drew its circle (POST /api/v1/plugins/draw-circle/circle)" \
            bash -c 'grep -q "\"completed\":3" <<<"$1"' _ "$c"
    else
        msg="WASM plugin (plugins/examples/build.sh failed: see $logs/plugin-build.log)"
        if [ -n "${CI:-}" ]; then fail "$msg"; else skip "$msg"; fi
    fi
fi

# ----------------------------------------------------- service manager
phase "config change + restart (net stop / net start), access control on"
[ -n "$svc_port" ] || { svc_cfg_dir=$cfg_dir; svc_port=$port_a; }
port_b=$(free_port)
write_config "$svc_cfg_dir" "$port_b" auth
W net stop kuka-bridge >"$logs/net-stop.out"
check "net stop -> STOPPED, WIN32_EXIT_CODE 0 (graceful)" \
    bash -c "[ \"\$(grep -c 'stopped successfully' '$logs/net-stop.out')\" = 1 ]"
check "sc query: STOPPED with exit code 0" \
    bash -c "$(declare -f W svc_query svc_field wait_state); logs='$logs';
             wait_state STOPPED 15 && [ \"\$(svc_field WIN32_EXIT_CODE)\" = 0 ]"
W net start kuka-bridge >"$logs/net-start.out"
check "net start -> RUNNING" wait_state RUNNING 30
check "restarted service uses the new config (/health on :$port_b)" wait_health "$port_b" 20
check "old port :$svc_port closed" bash -c "! (exec 3<>/dev/tcp/127.0.0.1/$svc_port) 2>/dev/null"
svc_port=$port_b
admin_file="$svc_cfg_dir/initial-admin-token.txt"
check "first start with auth wrote initial-admin-token.txt (private DACL via SetFileSecurityW)" \
    test -s "$admin_file"
admin=$(grep '^kb_' "$admin_file" 2>/dev/null | head -1)
check "no token -> 401 unauthenticated" bash -c \
    "curl -sS -m 10 http://127.0.0.1:$svc_port/api/v1/state | grep -q unauthenticated"
check "admin token -> 200 (GET /api/v1/state)" \
    curl -fsS -m 10 -o /dev/null -H "authorization: Bearer $admin" "http://127.0.0.1:$svc_port/api/v1/state"
W_once_more "$logs/token-create.out" "$exe_win" token create --data-dir "$(winpath "$svc_cfg_dir")" \
    --name wine-viewer --role viewer
viewer=$(grep '^kb_' "$logs/token-create.out" | tr -d '\r' | head -1)
check "kuka-bridge.exe token create (console, service running) prints a token" test -n "$viewer"
# The service re-reads the token file periodically: wait (≤ 10 s) until it knows the token.
check "the running service accepts it: a viewer reads, cannot move (403)" bash -c "
    for _ in \$(seq 50); do
        curl -fsS -m 10 -o /dev/null -H 'authorization: Bearer $viewer' http://127.0.0.1:$svc_port/api/v1/state 2>/dev/null && break
        sleep 0.2
    done
    curl -fsS -m 10 -o /dev/null -H 'authorization: Bearer $viewer' http://127.0.0.1:$svc_port/api/v1/state &&
    curl -sS -m 10 -X POST -H 'authorization: Bearer $viewer' -H 'content-type: application/json' \
        -d '{\"motions\":[]}' http://127.0.0.1:$svc_port/api/v1/motions | grep -q forbidden"
if [ -n "${plugin:-}" ]; then
    p=$(curl -sS -m 10 -H "authorization: Bearer $admin" "http://127.0.0.1:$svc_port/api/v1/plugins/draw-circle" 2>&1)
    check "plugin loaded again at start from the compiled cache (from_cache true)" \
        bash -c 'grep -q "\"from_cache\":true" <<<"$1"' _ "$p"
fi

phase "sc stop / sc start"
W sc stop kuka-bridge >/dev/null
check "sc stop -> STOPPED" wait_state STOPPED 30
check "API down after stop" bash -c "! curl -fsS -m 2 http://127.0.0.1:$svc_port/health >/dev/null 2>&1"
W sc start kuka-bridge >/dev/null
check "sc start -> RUNNING" wait_state RUNNING 30
check "API up after start" wait_health "$svc_port" 20

phase "kuka-bridge service status/stop/start (CLI)"
W_once_more "$logs/cli-status.out" "$exe_win" service status
sed 's/^/      /' "$logs/cli-status.out" | head -8
check "service status: running" grep -qi "running" "$logs/cli-status.out"
check "service stop (waits until stopped)" bash -c \
    "timeout 120 wine '$exe_win' service stop >'$logs/cli-stop.out' 2>&1 && grep -q stopped '$logs/cli-stop.out'"
# The SCM agrees (sc query retried: one query right as the process exits
# failed once under Wine 8).
check "sc query -> STOPPED after the CLI stop" wait_state STOPPED 5
check "service start" bash -c \
    "timeout 120 wine '$exe_win' service start >'$logs/cli-start.out' 2>&1"
check "API up after CLI start" wait_health "$svc_port" 20

# ------------------------------------------------------------- failures
phase "kill the process"
W taskkill /F /IM kuka-bridge.exe >"$logs/taskkill.out"
check "taskkill /F terminates kuka-bridge.exe" grep -q "terminated" "$logs/taskkill.out"
check "API down after the kill" bash -c "sleep 1; ! curl -fsS -m 2 http://127.0.0.1:$svc_port/health >/dev/null 2>&1"
if wait_state STOPPED 6; then
    code=$(svc_field WIN32_EXIT_CODE)
    if [ "$code" != 0 ]; then pass "SCM records the kill as a failure (WIN32_EXIT_CODE $code)"; else
        fail "SCM records the kill as a failure (WIN32_EXIT_CODE 0)"; fi
else
    # Measured: Wine 8.0's services.exe does not watch service processes;
    # after a kill it reports RUNNING / exit 0 forever. Windows records
    # 1067 ERROR_PROCESS_ABORTED and runs the recovery actions.
    skip "SCM exit code after a kill: Wine $(wine --version 2>/dev/null | sed 's/wine-//') keeps reporting RUNNING/0 for a dead service process (Windows: STOPPED, 1067)"
fi
W sc start kuka-bridge >/dev/null
check "sc start after the kill -> RUNNING + API (manual recovery; Wine has no failure actions)" \
    bash -c "$(declare -f W svc_query svc_field wait_state health wait_health); logs='$logs';
             wait_state RUNNING 30 && wait_health $svc_port 20"

phase "failure exit code (service stops itself: broken config)"
W sc stop kuka-bridge >/dev/null
wait_state STOPPED 30 >/dev/null
cp "$svc_cfg_dir/kuka-bridge.toml" "$tmp/good.toml"
write_config "$svc_cfg_dir" 0 broken
W sc start kuka-bridge >/dev/null
wait_state STOPPED 30 >/dev/null
svc_query >"$logs/sc-after-config-error.txt"
w32=$(awk '$1=="WIN32_EXIT_CODE"{print $3}' "$logs/sc-after-config-error.txt")
sx=$(awk '$1=="SERVICE_EXIT_CODE"{print $3}' "$logs/sc-after-config-error.txt")
echo "      sc query: STATE $(awk '$1=="STATE"{print $4}' "$logs/sc-after-config-error.txt"), WIN32_EXIT_CODE $w32, SERVICE_EXIT_CODE $sx"
check "SCM records a failure: WIN32_EXIT_CODE 1066 (service-specific), SERVICE_EXIT_CODE 78 (config)" \
    test "$w32" = 1066 -a "$sx" = 78
cp "$tmp/good.toml" "$svc_cfg_dir/kuka-bridge.toml"
W sc start kuka-bridge >/dev/null
check "fixed config -> RUNNING + API" bash -c "$(declare -f W svc_query svc_field wait_state health wait_health); logs='$logs';
             wait_state RUNNING 30 && wait_health $svc_port 20"

phase "Event Log (WINEDEBUG=+eventlog on services.exe)"
evl="$logs/services-eventlog.log"
grep -a "eventlog:ReportEventW" "$evl" | sed 's/^/      /' | head -12
check "event: 'kuka-bridge service started'" grep -aq 'ReportEventW L"kuka-bridge service started' "$evl"
check "event: 'kuka-bridge service stopped'" grep -aq 'ReportEventW L"kuka-bridge service stopped' "$evl"
check "event: configuration error (as an error)" grep -aq 'err:eventlog:ReportEventW L".*configuration error' "$evl"

# ------------------------------------------------------------------ upgrade
# ProductVersion + 1 in the build field (MSI limits: 255.255.65535).
v=$(msiinfo export "$msi" Property | tr -d '\r' | awk -F'\t' '$1=="ProductVersion"{print $2}')
upgrade_version="${v%.*}.$((${v##*.} + 1))"
phase "major upgrade ($v -> $upgrade_version, same exe)"
# A second MSI around the installed exe, with a higher ProductVersion: its
# RemoveExistingProducts (after InstallValidate) removes the first product.
cp "$install_dir/kuka-bridge.exe" "$tmp/installed.exe"
msi2="$tmp/kuka-bridge-upgrade.msi"
if "$here/build-msi.sh" --exe "$tmp/installed.exe" --version "$upgrade_version" \
    --out "$msi2" >"$logs/build-msi-upgrade.log" 2>&1; then
    timeout 300 wine msiexec /i "$(winpath "$msi2")" /qn /l*v "$(winpath "$logs/msi-upgrade.log")" \
        >"$logs/msiexec-upgrade.out" 2>&1
    rc=$?
    check "msiexec /i (upgrade) exit 0" test "$rc" = 0
    check "upgrade removed the old product (RemoveExistingProducts ran)" \
        grep -aq "Action ended .*RemoveExistingProducts. Return value 1" "$logs/msi-upgrade.log"
    check "one KUKA Bridge product registered, version $upgrade_version" bash -c "
        out=\$(timeout 60 wine reg query 'HKLM\\Software\\Microsoft\\Windows\\CurrentVersion\\Uninstall' /s 2>/dev/null | tr -d '\r')
        [ \"\$(grep -c 'DisplayName.*KUKA Bridge' <<<\"\$out\")\" = 1 ] &&
        grep -q 'DisplayVersion.*$upgrade_version' <<<\"\$out\""
    check "service RUNNING after the upgrade" wait_state RUNNING 30
    check "API up after the upgrade, config kept" wait_health "$svc_port" 20
    check "files still installed after the upgrade" test -f "$install_dir/krl/PROTOCOL.md" -a -f "$install_dir/kuka-bridge.exe"
    msi=$msi2 # the installed product is now this one
else
    fail "build the upgrade MSI (see $logs/build-msi-upgrade.log)"
fi

# ---------------------------------------------------------------- uninstall
phase "msiexec /x"
timeout 300 wine msiexec /x "$(winpath "$msi")" /qn /l*v "$(winpath "$logs/msi-uninstall.log")" \
    >"$logs/msiexec-uninstall.out" 2>&1
rc=$?
if [ "$rc" = 0 ]; then pass "msiexec /x exit 0"; else
    fail "msiexec /x exit $rc (see $logs/msi-uninstall.log)"; fi
# The script (after "InstallFinalize" starts) is what really runs, in order.
check "uninstall script: StopServices, then WaitForServiceExit, then RemoveFiles" bash -c "
    tr -d '\r' <'$logs/msi-uninstall.log' | sed -n '/^Action start .*InstallFinalize/,\$p' |
    sed -n 's/^Action start [0-9:]*: \(StopServices\|WaitForServiceExit\|RemoveFiles\)\.\$/\1/p' | paste -sd' ' |
    grep -qx 'StopServices WaitForServiceExit RemoveFiles'"

phase "nothing left"
check "service gone (sc query)" bash -c "! timeout 60 wine sc query kuka-bridge 2>/dev/null | grep -q SERVICE_NAME"
check "no kuka-bridge.exe process in this prefix" test -z "$(our_processes)"
check "Program Files\\kuka-bridge gone" test ! -e "$install_dir"
check "Event Log source key gone" bash -c "! timeout 60 wine reg query '$evl_key' >/dev/null 2>&1"
check "API down" bash -c "! curl -fsS -m 2 http://127.0.0.1:$svc_port/health >/dev/null 2>&1"
check "config and data kept in ProgramData (uninstall without --purge)" test -f "$cfg_dir/kuka-bridge.toml"

summary
[ "$failed" = 0 ]
