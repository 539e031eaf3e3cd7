#!/usr/bin/env node
// Decodes Sparkplug B payloads with Eclipse Tahu's own JavaScript codec (npm
// `sparkplug-payload`, what Node-RED's Sparkplug nodes use) — a second reader beside
// sparkplug_decode.py, to prove every host reads the bridge's metrics alike.
//
//   tahu_decode.js FILE   a line per message: "<topic> <payload in hex>"
//
// prints a JSON line per message: {"topic", "payload": {"seq", "metrics": [{"name",
// "type", "value"}]}} with Tahu's value as it gives it (a 64-bit Long as a number, null when
// Tahu reads none), or {"topic", "error"} when the codec refused the bytes. The codec is found
// in UNIMA_TAHU_DIR (scripts/install-deps.sh puts it in /usr/local/lib/unima-bridge-tests/tahu).
'use strict';
const fs = require('fs');
const path = require('path');

const tahuDir = process.env.UNIMA_TAHU_DIR || '/usr/local/lib/unima-bridge-tests/tahu';
const { decodePayload } = require(path.join(tahuDir, 'node_modules', 'sparkplug-payload')).get('spBv1.0');

function plain(value) {
  if (value === null || value === undefined) return null;
  if (typeof value === 'object' && typeof value.toNumber === 'function') return value.toNumber();  // a Long
  return value;
}

for (const line of fs.readFileSync(process.argv[2], 'utf8').split('\n')) {
  if (!line) continue;
  const space = line.indexOf(' ');
  const topic = line.slice(0, space);
  try {
    const payload = decodePayload(Buffer.from(line.slice(space + 1), 'hex'));
    const metrics = (payload.metrics || []).map((m) => ({ name: m.name, type: m.type, value: plain(m.value) }));
    console.log(JSON.stringify({ topic, payload: { seq: plain(payload.seq), metrics } }));
  } catch (e) {
    console.log(JSON.stringify({ topic, error: String(e) }));
  }
}
