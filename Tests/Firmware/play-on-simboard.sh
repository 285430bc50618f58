#!/usr/bin/env bash
# ctest firmware_play_pty: the real `armadillo play --port` against the reference firmware running in
# simavr behind a pseudo-terminal (simboard-pty). Proves the host program and the firmware talk;
# wall-clock figures here are NOT the board's (simavr runs slower than real time, which the bridge
# prints) — the quantitative loop figures come from tests_firmware_loop in simulated time.
# usage: play-on-simboard.sh SIMBOARD_PTY ARMADILLO WORKDIR [--v2]
#   --v2: the host offers the v2 framing; the summary must then say the link ran it ("v2":true).
set -euo pipefail
simboard=$1; armadillo=$2; dir=$3; v2=${4:-}
tag=${v2:+-v2}
link="$dir/simboard-pty$tag.link"
log="$dir/simboard-play$tag.csv"
rm -f "$link" "$log"
"$simboard" --link "$link" --seconds 60 --motion sweeps > "$dir/simboard-pty$tag.out" 2>&1 &
pid=$!
trap 'kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true' EXIT
for _ in $(seq 1 100); do [ -e "$link" ] && break; sleep 0.1; done
[ -e "$link" ] || { echo "simboard-pty did not create $link"; cat "$dir/simboard-pty$tag.out"; exit 1; }
sleep 1   # let the simulated board boot (MPU set-up) before the host connects
summary=$("$armadillo" play --scene monitor --port "$link" --seconds 8 --no-audio --log "$log" $v2 | tail -n 1)
kill -INT "$pid"; wait "$pid" || true; trap - EXIT
cat "$dir/simboard-pty$tag.out"
echo "armadillo play --port (simavr firmware): $summary"
packets=$(printf '%s' "$summary" | sed -n 's/.*"packets":\([0-9]*\).*/\1/p')
rows=$(($(grep -vc '^#' "$log") - 1))
echo "session log rows: $rows"
[ -n "$packets" ] && [ "$packets" -ge 100 ] || { echo "too few packets: ${packets:-none}"; exit 1; }
[ "$rows" -ge 100 ] || { echo "session log too short"; exit 1; }
if [ -n "$v2" ]; then
    printf '%s' "$summary" | grep -q '"v2":true' || { echo "the host did not run v2 with the firmware"; exit 1; }
fi
