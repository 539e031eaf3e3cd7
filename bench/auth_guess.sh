#!/usr/bin/env bash
# Modbus latency while a peer guesses passwords (issue 29, docs/performance.md): one daemon
# with `http.users` holding a bcrypt hash of cost 12 (~0.25–0.35 s a check); one Modbus
# client (unima-bench-load, FC4 × 16, 1 connection, so each request waits for the last)
# in paired rounds whose order alternates: idle, and while bench/auth_guesser.py sends
# wrong passwords from 127.0.0.2 on 4 connections as fast as it is answered (waiting what
# Retry-After says when told to; IMPATIENT=S: S seconds instead, 0.01 a guesser that
# ignores it and costs the loop an HTTP answer each time). Reports p50 and p99 of each
# (medians over the rounds), the p99 ratio, and what the guesser got back (checked and
# refused 401, told to wait 429, 503).
# Usage: [IMPATIENT=S] bench/auth_guess.sh [BUILD_DIR] [ROUNDS] [SECONDS] [COST]
#        (default build-release 5 3 12)
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/paired_rounds.sh
cost=${4:-12}

modbus=$(free_port); http=$(free_port)
hash=$(python3 -W ignore -c "import crypt; print(crypt.crypt('the right one', crypt.mksalt(crypt.METHOD_BLOWFISH, rounds=1 << $cost)))")
echo "technician:$hash" > "$work/http-users"
{
  echo "unimabus: { transport: sim, sim: { seed: 1, period: 1s } }"
  echo "modbus: { tcp: { listen: 127.0.0.1, port: $modbus } }"
  echo "devices: { D1: { type: unigen-chp, address: 5 } }"
  echo "log: { level: warn }"
  echo "status: { socket: $work/bridge.sock }"
  echo "state: { file: none }"
  echo "http: { listen: 127.0.0.1, port: $http, users: $work/http-users }"
} > "$work/bridge.yaml"
"$bridged" --config "$work/bridge.yaml" > "$work/bridge.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do (exec 3<>/dev/tcp/127.0.0.1/"$modbus") 2>/dev/null && break; sleep 0.05; done

latency() { "$load" --port "$modbus" --connections 1 --function 4 --address 4352 --quantity 16 --duration "$seconds" --warmup 0.3 --json; }
guessing() {  # the guesser runs for the whole round
  python3 bench/auth_guesser.py --port "$http" --source 127.0.0.2 --connections 4 ${IMPATIENT:+--impatient "$IMPATIENT"} \
    --seconds "$(python3 -c "print($seconds + 1.5)")" >> "$work/guesses.json" &
  local guesser=$!
  sleep 0.5  # its first checks are under way
  latency
  wait "$guesser"
}

idle_p50=(); idle_p99=(); busy_p50=(); busy_p99=(); ratios=()
for round in $(seq "$rounds"); do
  if [ $((round % 2)) = 1 ]; then a=$(latency); b=$(guessing)
  else b=$(guessing); a=$(latency); fi
  idle_p50+=("$(field p50_us <<< "$a")"); idle_p99+=("$(field p99_us <<< "$a")")
  busy_p50+=("$(field p50_us <<< "$b")"); busy_p99+=("$(field p99_us <<< "$b")")
  ratios+=("$(python3 -c "print($(field p99_us <<< "$b") / $(field p99_us <<< "$a"))")")
  echo "round $round: p99 idle ${idle_p99[-1]} us, while guessing ${busy_p99[-1]} us" >&2
done
python3 - "$work/guesses.json" "$rounds" "$cost" "$(median "${idle_p50[@]}")" "$(median "${idle_p99[@]}")" \
  "$(median "${busy_p50[@]}")" "$(median "${busy_p99[@]}")" "$(median "${ratios[@]}")" <<'PY'
import json, sys
rounds = [json.loads(line) for line in open(sys.argv[1])]
n, cost, idle50, idle99, busy50, busy99, ratio = sys.argv[2:9]
seconds = sum(r["seconds"] for r in rounds)
status = lambda code: sum(r["statuses"].get(code, 0) for r in rounds) / seconds
print(f"| Modbus FC4 × 16, 1 connection | idle | one peer guessing (bcrypt cost {cost}) | ratio (median of {n} paired rounds) |")
print("|---|---|---|---|")
print(f"| p50, µs | {float(idle50):.0f} | {float(busy50):.0f} | |")
print(f"| p99, µs | {float(idle99):.0f} | {float(busy99):.0f} | {ratio} |")
print(f"| guesses checked and refused (401), per second | | {status('401'):.1f} | |")
print(f"| guesses told to wait (429), per second | | {status('429'):.0f} | |")
print(f"| guesses told to come back (503), per second | | {status('503'):.1f} | |")
PY
