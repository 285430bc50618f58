#!/usr/bin/env bash
# Endurance run (issue 48, docs/SECURITY.md "Endurance"): the live instrument for MINUTES with
# every output on — `armadillo play --simulate --scene theremin` with a session log, a tactile
# CSV, a WAV recording, OSC out to a local UDP receiver this script runs, MQTT publish (a mapping
# with MQTT and OSC destinations) to a Mosquitto it starts on a free loopback port, the tactors on
# JACK's dummy backend, the stage-control port open on loopback, and the web page on loopback with
# a client that keeps its event stream open and asks for the status once a second (as an open
# page and a screen reader's refresh do). Every EVERY minutes (10 by
# default; and once at minute 1, the memory baseline) and at the end it prints one row: resident
# memory (VmRSS), its growth since minute 1, the control rate, the sensor-to-motor latency
# p50/p99 (since the start), and what was lost: bad packets and gaps of the link, OSC datagrams
# sent by play against those the receiver got (and malformed ones), MQTT messages published
# against those a subscriber got (and the outbox's drops), tactor records dropped, and the web
# page's events received, status requests answered and requests that failed.
# The last line says `soak: ok` or `soak: FAILED (why)` (exit 1): memory growth above 2 MiB
# after minute 1, a bad packet, a gap, anything dropped, or a web request that failed (or no events).
#
#   bash scripts/soak.sh MINUTES [--every MINUTES] [--bin PATH] [--keep]
#
# --keep leaves the work folder (logs, recording, status) and says where. Everything the script
# started is stopped on exit (also on Ctrl-C).
set -euo pipefail
cd "$(dirname "$0")/.."

usage() { echo "usage: bash scripts/soak.sh MINUTES [--every MINUTES] [--bin PATH] [--keep]" >&2; exit 2; }
[ $# -ge 1 ] || usage
minutes=$1; shift
every=10
bin=build/bin/armadillo
keep=0
while [ $# -gt 0 ]; do
    case "$1" in
        --every) every=${2:?}; shift 2 ;;
        --bin) bin=${2:?}; shift 2 ;;
        --keep) keep=1; shift ;;
        *) usage ;;
    esac
done
python3 -c "import sys; m, e = float('$minutes'), float('$every'); sys.exit(0 if m > 0 and e > 0 else 1)" 2>/dev/null || usage
[ -x "$bin" ] || { echo "soak: $bin is not built (bash scripts/build.sh armadillo)" >&2; exit 2; }
for tool in mosquitto jackd jack_wait mosquitto_sub python3; do
    command -v "$tool" > /dev/null || [ -x "/usr/sbin/$tool" ] || { echo "soak: $tool is missing (scripts/install-deps.sh)" >&2; exit 2; }
done
mosquitto=$(command -v mosquitto || echo /usr/sbin/mosquitto)

work=$(mktemp -d "${TMPDIR:-/tmp}/armadillo-soak.XXXXXX")
pids=()
cleanup() {
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do kill "${pids[$i]}" 2> /dev/null || true; done
    for p in "${pids[@]}"; do wait "$p" 2> /dev/null || true; done
    if [ "$keep" = 1 ]; then echo "soak: files kept in $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

free_port() { python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
wait_for() {   # wait_for SECONDS COMMAND…: polls until COMMAND succeeds; false after SECONDS
    local deadline=$((SECONDS + $1)); shift
    until "$@" 2> /dev/null; do
        [ $SECONDS -lt $deadline ] || return 1
        sleep 0.1
    done
}

# The OSC receiver: counts datagrams, and those that are not an OSC message or bundle (an address
# or "#bundle" first, a length that is a multiple of 4); writes "received malformed" once a second.
osc_port=$(free_port)
python3 - "$osc_port" "$work/osc-count" << 'PY' &
import os, socket, sys, time
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
s.bind(("127.0.0.1", int(sys.argv[1])))
s.settimeout(0.2)
received = malformed = 0
written = time.monotonic()
while True:
    try:
        d = s.recv(65536)
        received += 1
        if len(d) % 4 != 0 or not (d.startswith(b"/") or d.startswith(b"#bundle\0")):
            malformed += 1
    except socket.timeout:
        pass
    if time.monotonic() - written >= 0.5:
        written = time.monotonic()
        with open(sys.argv[2] + ".tmp", "w") as f:
            f.write(f"{received} {malformed}\n")
        os.replace(sys.argv[2] + ".tmp", sys.argv[2])
PY
pids+=($!)

# Mosquitto on a free loopback port, and a subscriber that counts what arrives.
mqtt_port=$(free_port)
printf 'listener %s 127.0.0.1\nallow_anonymous true\npersistence false\nlog_dest none\nmax_queued_messages 100000\n' "$mqtt_port" > "$work/mosquitto.conf"
"$mosquitto" -c "$work/mosquitto.conf" &
pids+=($!)
wait_for 20 bash -c "exec 3<>/dev/tcp/127.0.0.1/$mqtt_port" || { echo "soak: mosquitto did not start" >&2; exit 1; }
mosquitto_sub -h 127.0.0.1 -p "$mqtt_port" -t 'armadillo/soak/#' > "$work/mqtt-received" &
pids+=($!)

# JACK's dummy backend under a name of its own.
export JACK_DEFAULT_SERVER="armadillo_soak_$$"
jackd -n "$JACK_DEFAULT_SERVER" -d dummy -r 48000 -p 256 > "$work/jackd.log" 2>&1 &
pids+=($!)
wait_for 20 jack_wait -c > /dev/null || { echo "soak: jackd (dummy) did not start" >&2; exit 1; }

# A mapping with both kinds of destination: OSC (every change) and MQTT (rate-limited).
cat > "$work/soak-map.json" << 'JSON'
{"version": 1, "name": "soak",
 "mappings": [
  {"label": "elevation as OSC", "source": "elevation", "in": [-90, 90], "out": [0, 1], "to": {"osc": "/soak/elevation", "args": ["$value"], "types": "f"}},
  {"label": "azimuth as OSC", "source": "azimuth", "in": [-180, 180], "out": [0, 1], "to": {"osc": "/soak/azimuth", "args": ["$value"], "types": "f"}},
  {"label": "elevation as MQTT", "source": "elevation", "in": [-90, 90], "out": [0, 100],
   "to": {"mqtt": {"topic": "armadillo/soak/elevation", "payload": "{round}", "qos": 0, "retain": false, "rate": 10}}},
  {"label": "roll as MQTT", "source": "roll", "in": [-180, 180], "out": [0, 100],
   "to": {"mqtt": {"topic": "armadillo/soak/roll", "payload": "{round}", "qos": 1, "retain": false, "rate": 5}}}]}
JSON

# The web page's client: the event stream held open (reopened and counted if it ends) and
# GET /api/status once a second until 3 s before play's planned end (the page closes with it);
# writes "events ok failed reopened" twice a second.
seconds=$(python3 -c "print(round(float('$minutes') * 60))")
web_port=$(free_port)
python3 - "$web_port" "$work/web-count" "$seconds" << 'PY' &
import http.client, json, os, sys, threading, time
port, out = int(sys.argv[1]), sys.argv[2]
stopAsking = time.monotonic() + float(sys.argv[3]) - 3.0
c = {"events": 0, "ok": 0, "failed": 0, "reopened": 0}
def stream():
    first = True
    while True:
        try:
            h = http.client.HTTPConnection("127.0.0.1", port, timeout=10)
            h.request("GET", "/events")
            r = h.getresponse()
            if r.status != 200: raise OSError(f"status {r.status}")
            if not first: c["reopened"] += 1
            first = False
            while True:
                line = r.fp.readline()
                if not line: break
                if line.startswith(b"data:"): c["events"] += 1
        except OSError:
            pass
        time.sleep(0.5)
threading.Thread(target=stream, daemon=True).start()
written = nextAsk = time.monotonic()
while True:
    now = time.monotonic()
    if now >= nextAsk and now < stopAsking:
        nextAsk += 1.0
        try:
            h = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
            h.request("GET", "/api/status")
            r = h.getresponse()
            body = r.read()
            if r.status == 200 and "pose" in json.loads(body): c["ok"] += 1
            else: c["failed"] += 1
            h.close()
        except (OSError, ValueError):
            if c["ok"] > 0: c["failed"] += 1   # before the first answer: the page is not up yet
    if now - written >= 0.5:
        written = now
        with open(out + ".tmp", "w") as f:
            f.write(f"{c['events']} {c['ok']} {c['failed']} {c['reopened']}\n")
        os.replace(out + ".tmp", out)
    time.sleep(0.05)
PY
pids+=($!)

control_port=$(free_port)
"$bin" play --simulate --scene theremin --seconds "$seconds" --out "$work/audio.wav" --log "$work/session.csv" \
    --tactile "$work/tactile.csv" --osc-out "127.0.0.1:$osc_port" --map "$work/soak-map.json" --mqtt "127.0.0.1:$mqtt_port" \
    --tactors jack --tactor-model lra --control-in "$control_port" --web "$web_port" --status-file "$work/status.json" \
    > "$work/summary.json" 2> "$work/play.err" &
play=$!
pids+=($play)

# One row of the table from the status file (or the final summary) and the counters on our side.
row() {   # row LABEL JSONFILE… RSS_KIB (a later file's members over an earlier one's)
    python3 - "$@" "$work/web-count" "$work/osc-count" "$work/mqtt-received" "$work/baseline" << 'PY'
import json, os, sys
label, paths, rss = sys.argv[1], sys.argv[2:-5], int(sys.argv[-5] or 0)
web = (open(sys.argv[-4]).read().split() if os.path.exists(sys.argv[-4]) else []) + ["0"] * 4
s = {}
for path in paths:
    try:
        s.update(json.loads(open(path).read().strip().splitlines()[-1]))
    except Exception:
        pass
osc_count, mqtt_file, baseline = sys.argv[-3:]
received, malformed = (open(osc_count).read().split() + ["0", "0"])[:2] if os.path.exists(osc_count) else ("0", "0")
mqtt_got = sum(1 for _ in open(mqtt_file)) if os.path.exists(mqtt_file) else 0
base = int(open(baseline).read()) if os.path.exists(baseline) else rss
m = s.get("mqtt", {})
growth = (rss - base) / 1024.0 if rss else float("nan")
print(f"{label:>7} {rss / 1024.0:8.1f} {growth:+7.2f} {s.get('rate_hz', 0):7.1f} {s.get('latency_p50_us', 0):7.0f} {s.get('latency_p99_us', 0):7.0f}"
      f" {s.get('packets', 0):10d} {s.get('bad_packets', 0):4d} {s.get('gaps', 0):4d}"
      f" {s.get('mapping_osc_messages', 0):9d} {int(received):9d} {int(malformed):4d} {s.get('mapping_dropped', 0):5d}"
      f" {m.get('published', 0):7d} {mqtt_got:7d} {m.get('outbox_dropped', 0):5d}"
      f" {s.get('tactor_frames', 0):9d} {s.get('tactor_dropped', 0):5d}"
      f" {int(web[0]):7d} {int(web[1]):6d} {int(web[2]):5d}", flush=True)
PY
}
rss_kib() { awk '/^VmRSS:/ {print $2}' "/proc/$play/status" 2> /dev/null || echo 0; }

echo "soak: $minutes min of 'armadillo play --simulate --scene theremin' with every output on (pid $play; rows every $every min)"
printf '%7s %8s %7s %7s %7s %7s %10s %4s %4s %9s %9s %4s %5s %7s %7s %5s %9s %5s %7s %6s %5s\n' \
    minute RSS_MiB growth rate_Hz p50_us p99_us packets bad gaps osc_sent osc_recv osc! osc_d mqtt_pub mqtt_rcv mq_d tactor_fr t_drop \
    web_ev web_ok web!
start=$SECONDS
next=60   # the first row at minute 1: the memory baseline
every_s=$(python3 -c "print(max(1, round(float('$every') * 60)))")
while kill -0 "$play" 2> /dev/null; do
    if [ $((SECONDS - start)) -ge $next ]; then
        rss=$(rss_kib)
        [ -f "$work/baseline" ] || echo "$rss" > "$work/baseline"
        row "$(python3 -c "print(f'{($SECONDS - $start) / 60:.1f}')")" "$work/status.json" "$rss"
        last_rss=$rss
        next=$(( next == 60 && every_s > 60 ? every_s : next + every_s ))
    fi
    sleep 1
done
status=0
wait "$play" || status=$?
sleep 1   # the receivers' last counts (written twice a second)
if [ "$status" != 0 ]; then
    echo "soak: armadillo play ended with exit code $status:" >&2
    tail -5 "$work/play.err" >&2
    keep=1
    exit 1
fi
row end "$work/status.json" "$work/summary.json" "${last_rss:-0}"
echo "(end: the final summary; latency and RSS as last measured while it ran)"

verdict=$(python3 - "$work/summary.json" "$work/osc-count" "$work/mqtt-received" "$work/baseline" "${last_rss:-0}" "$work/web-count" << 'PY'
import json, sys
s = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
received, malformed = map(int, open(sys.argv[2]).read().split())
mqtt_got = sum(1 for _ in open(sys.argv[3]))
try:
    growth = (int(sys.argv[5]) - int(open(sys.argv[4]).read())) / 1024.0
except Exception:
    growth = 0.0
m = s.get("mqtt", {})
why = []
if growth > 2.0: why.append(f"memory grew {growth:.2f} MiB after minute 1")
if s.get("bad_packets", 0): why.append(f"{s['bad_packets']} bad packets")
if s.get("gaps", 0): why.append(f"{s['gaps']} gaps (longest {s.get('longest_gap_s', 0)} s)")
if malformed: why.append(f"{malformed} malformed OSC datagrams")
if received != s.get("mapping_osc_messages", 0): why.append(f"OSC: {s.get('mapping_osc_messages', 0)} sent, {received} received")
if s.get("mapping_dropped", 0): why.append(f"{s['mapping_dropped']} mapping messages dropped")
if m.get("outbox_dropped", 0): why.append(f"{m['outbox_dropped']} MQTT messages dropped from the outbox")
if mqtt_got < m.get("published", 0): why.append(f"MQTT: {m.get('published', 0)} published, {mqtt_got} received")
if s.get("tactor_dropped", 0): why.append(f"{s['tactor_dropped']} tactor records dropped")
events, asked, failed, reopened = map(int, open(sys.argv[6]).read().split())
if failed: why.append(f"web page: {failed} status requests failed")
if events == 0 or asked == 0: why.append(f"web page: {events} events, {asked} status answers")
print("ok" if not why else "FAILED (" + "; ".join(why) + ")")
PY
)
echo "soak: $verdict"
[ "$verdict" = ok ]
