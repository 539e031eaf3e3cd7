// The front page (docs/configuration.md, `http`): the register map once from /api/registers, then everything
// live from /api/events (web/live_view.hpp): a full picture on connecting, changes after.
'use strict';

const MAX_LINES = 200;
const cells = new Map();      // "D1/engine_speed" -> the cells of that value (its bank's, a read block's)
const byAddress = new Map();  // "0x1100" -> the cells of the values that read that register
let source = null;

const element = (tag, attributes = {}, text) => {
  const e = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes)) e.setAttribute(name, value);
  if (text !== undefined) e.textContent = text;
  return e;
};

// A path of the daemon's API, as a whole URL of the page's origin: a page opened as
// https://name:password@host/ has its name and password in its own URL, and fetch() refuses
// a URL resolved against it ("cannot be constructed from a URL that includes credentials");
// the browser sends the name and password it was given to the same origin all the same.
const api = path => new URL(path, location.origin).href;

const hex = (number, digits = 4) => '0x' + number.toString(16).toUpperCase().padStart(digits, '0');

// A number as the reader's browser writes one: thousands grouped, every decimal the scale
// gave kept (a knock level of 0.78125 % steps is 100.78125, not 100.781).
const numberText = number => number.toLocaleString(undefined, { maximumFractionDigits: 6 });

// Seconds past this are a counter (operating hours): read in hours, the seconds in the title.
const LONG_SECONDS = 10 * 3600;
const inHours = seconds => (seconds / 3600).toLocaleString(undefined, { minimumFractionDigits: 1, maximumFractionDigits: 1 }) + ' h';

// A value as the daemon decoded it (values/): its reading in its unit, or why it has none,
// in words ("not measured", "off-line", "not set", "not mapped"). A bit word is bits, named
// by the seed or not: in hex, as a technician compares it with the unit's manual; its named
// bits have rows of their own.
function shown(value, unit, type) {
  if (value.state !== 'ok') return value.state;
  if (typeof value.value === 'boolean') return value.value ? 'on' : 'off';
  if (typeof value.value === 'string') return `"${value.value}"`;
  if (type === 'bits') return hex(value.value);
  if (unit === 's' && Math.abs(value.value) >= LONG_SECONDS) return inHours(value.value);
  return numberText(value.value) + (unit ? ' ' + unit : '');
}

// What the cell's title adds to its register: the exact reading when the cell shows it
// another way, or that the seed's table gives the number no unit.
function readingNote(value, unit, type) {
  if (value.state !== 'ok' || typeof value.value !== 'number' || type === 'bits') return '';
  if (unit === 's' && Math.abs(value.value) >= LONG_SECONDS) return `${numberText(value.value)} s`;
  return unit ? '' : 'no unit in the device table';
}

// A bank's table: one row per value, at the first register it reads; a register without
// values (a reserve) is not listed; a read block lists its source's values, a write block
// that it is write only.
function bankTable(bank, rows) {
  const table = element('table');
  const head = element('tr');
  for (const [name, cls] of [['address', 'address'], ['name', ''], ['label', 'label'], ['value', '']]) head.append(element('th', cls ? { class: cls } : {}, name));
  table.append(head);
  const addRow = (row, key, name, label, unit, value, type) => {
    const tr = element('tr');
    const cell = element('td', { class: 'value', 'data-address': row.address, 'data-key': key });
    cell.dataset.unit = unit || '';
    cell.dataset.type = type || '';
    tr.append(element('td', { class: 'address' }, row.address), element('td', {}, name),
              element('td', { class: 'label', lang: 'cs' }, label), cell);
    table.append(tr);
    if (!cells.has(key)) cells.set(key, []);
    cells.get(key).push(cell);
    if (!byAddress.has(row.address)) byAddress.set(row.address, []);
    byAddress.get(row.address).push(cell);
    setValue(key, value, false);
    setRaw(row.address, row.value);
  };
  const listed = new Set();
  for (const row of rows) {
    if (row.bank === 'write') {  // a write block: nothing to read back
      addRow(row, `write/${row.id}`, row.id, row.label, '', { value: null, state: 'write only' });
      continue;
    }
    for (const value of row.values) {
      const key = `${value.bank}/${value.name}`;
      if (listed.has(key)) continue;  // a 32-bit pair: listed at its low word
      listed.add(key);
      // A read block shows its source's value under the block's name.
      const name = bank === 'read' ? `${row.id} = ${value.bank}.${value.name}` : value.name;
      addRow(row, key, name, value.label, value.unit, value, value.type);
    }
  }
  return { table, count: listed.size };
}

function buildBanks(rows) {
  const banks = document.getElementById('banks');
  banks.replaceChildren(element('h2', {}, 'Banks'));
  cells.clear();
  byAddress.clear();
  const byBank = new Map();
  for (const row of rows) {
    if (!byBank.has(row.bank)) byBank.set(row.bank, []);
    byBank.get(row.bank).push(row);
  }
  for (const [bank, bankRows] of byBank) {
    const details = element('details', { class: 'bank', 'data-bank': bank });
    details.open = byBank.size <= 4 || bank.startsWith('D');
    const { table, count } = bankTable(bank, bankRows);
    const values = count || bankRows.length;
    details.append(element('summary', {}, `${bank} — ${values} value${values === 1 ? '' : 's'} from ${bankRows[0].address}`), table);
    banks.append(details);
  }
}

function setValue(key, value, flash = true) {
  for (const cell of cells.get(key) || []) showValue(cell, value, flash);
}

function showValue(cell, value, flash) {
  cell.textContent = shown(value, cell.dataset.unit, cell.dataset.type);
  cell.dataset.note = readingNote(value, cell.dataset.unit, cell.dataset.type);
  cell.title = cellTitle(cell);
  cell.dataset.state = value.state;
  if (value.set === false) cell.dataset.set = 'false';
  else delete cell.dataset.set;
  if (flash) {
    cell.classList.add('changed');
    setTimeout(() => cell.classList.remove('changed'), 50);
  }
}

// The raw register beside the values read from it: the cells' title, for the technician
// who compares with a Modbus read, and the reading's note.
function cellTitle(cell) {
  const register = cell.dataset.raw === undefined ? '' : cell.dataset.raw === '' ? `${cell.dataset.address}: not readable`
                                                                                  : `${cell.dataset.address} = ${cell.dataset.raw}`;
  return [register, cell.dataset.note].filter(Boolean).join('; ');
}

function setRaw(address, raw) {
  for (const cell of byAddress.get(address) || []) {
    cell.dataset.raw = raw === null || raw === undefined ? '' : String(raw);
    cell.title = cellTitle(cell);
  }
}

function chip(bank, type, online, configured = true) {
  return element('span', { class: 'chip', 'data-bank': bank, 'data-online': String(online), 'data-configured': String(configured),
                           title: type || 'not configured' }, type ? `${bank} ${type}` : bank);
}

// An LED that shows frames (SPEC §8): lit for its moment (lit_ms) after each. The panel
// comes at most every 250 ms, longer than the moment: a count that moved since the last
// panel blinks it once.
const ledFrames = new Map();
function showLed(id, led) {
  const lamp = document.getElementById(id);
  const before = ledFrames.get(id);
  ledFrames.set(id, led.frames);
  if (!led.on && (before === undefined || before === led.frames)) return;
  lamp.dataset.on = 'true';
  clearTimeout(lamp.offTimer);
  lamp.offTimer = setTimeout(() => { lamp.dataset.on = 'false'; }, led.lit_ms);
}

// A capture indicator: its value green when a read carried it, red when a write did (seed
// 004 §2), grey before either.
function indicatorBox(indicator, i) {
  const access = indicator.access || 'none';
  const box = element('div', { class: `indicator access-${access}`, 'data-indicator': String(i + 1), 'data-access': access });
  const value = element('div', { class: 'value' });
  value.append(element('span', { class: 'lamp' }), indicator.value === null ? '—' : `${hex(indicator.value)} (${indicator.value})`);
  box.append(element('div', { class: 'what' }, `${i + 1}: ad ${indicator.address}, register ${hex(indicator.register)}`),
             value,
             element('div', { class: 'what' }, indicator.access ? `${indicator.access} ${indicator.time}` : 'not seen'));
  return box;
}

// A box per RS-485 line (SPEC §18): its role, device and settings, what it sent and
// received; a line whose device is not open, or that counts errors, in the error colour.
function serialLineBox(line) {
  const box = element('div', { class: 'serial-line', 'data-line': line.line, 'data-open': String(line.open) });
  box.append(element('h4', {}, `${line.line}: ${line.role}`),
             element('p', line.open ? {} : { class: 'problem' }, `${line.device} ${line.settings}${line.open ? '' : ' — not open'}`),
             element('p', line.errors > 0 ? { class: 'problem' } : {},
                     `${line.frames_sent} sent, ${line.frames_received} received, ${line.errors} errors, ${line.queue} queued`));
  return box;
}

function showSerialLines(lines) {
  const box = document.getElementById('serial-lines');
  box.hidden = !lines || lines.length === 0;
  if (box.hidden) return;
  box.replaceChildren(element('h3', {}, 'RS-485 lines'), ...lines.map(serialLineBox));
}

// The gateway's units (SPEC §14): one row each, a unit that stopped answering in red with
// since when, so a technician sees a silent slave without reading the monitor.
function gatewayTable(units) {
  const table = element('table');
  const head = element('tr');
  for (const name of ['unit', 'state', 'requests', 'answered', 'exceptions', 'time-outs', 'busy', 'queue', 'wait ms (mean)'])
    head.append(element('th', {}, name));
  table.append(head);
  for (const u of units) {
    const tr = element('tr', { 'data-unit': String(u.unit), 'data-state': u.state });
    const state = u.since ? `${u.state} since ${u.since}` : u.state;
    tr.append(element('td', { class: 'count' }, String(u.unit)), element('td', { class: 'state' }, state));
    for (const count of [u.requests, u.answered, u.exceptions, u.timeouts + u.bad_frames, u.busy, u.queue_depth, u.wait_ms_mean])
      tr.append(element('td', { class: 'count' }, String(count)));
    table.append(tr);
  }
  return table;
}

function showGateway(gateway) {
  const box = document.getElementById('gateway');
  box.hidden = !gateway;
  if (!gateway) return;
  const title = element('h3', {}, `Gateway: units ${gateway.routes}`);
  box.replaceChildren(title, gateway.units.length ? gatewayTable(gateway.units) : element('p', {}, 'no client has asked for a unit yet'));
}

// A time of the status document ("2026-11-27T10:35:19.501234Z") as an operator reads it.
const when = time => time.slice(0, 19).replace('T', ' ') + ' UTC';
const TAKEOVER_RECENT_MS = 3600 * 1000;  // a takeover within the hour still needs looking at

// One line of the northbound box; `problem` marks it in the error colour.
const northLine = (text, problem = false) => element('p', problem ? { class: 'problem' } : {}, text);

// MQTT (SPEC §15): connected or not since when, the history buffer, the last takeover.
function mqttSection(m) {
  const section = element('div', { 'data-section': 'mqtt', 'data-connected': String(m.connected) });
  section.append(element('h4', {}, 'MQTT'));
  section.append(m.connected
    ? northLine(`connected to ${m.broker} as ${m.client_id} since ${when(m.since)}`)
    : northLine(`not connected to ${m.broker} (as ${m.client_id}) since ${when(m.since)}` + (m.last_error ? `: ${m.last_error}` : ''), true));
  if (m.buffer) {
    const b = m.buffer;
    section.append(northLine(`history buffer: ${b.messages} message${b.messages === 1 ? '' : 's'} (${b.bytes} bytes) waiting, ` +
                             `${b.history_sent} sent as history`, b.messages > 0 && !m.connected));
    section.append(northLine(`${b.dropped} dropped because the buffer was full`, b.dropped > 0));
  } else {
    section.append(northLine('no history buffer: an outage keeps only the present values'));
  }
  const recent = m.last_takeover && Date.now() - Date.parse(m.last_takeover) < TAKEOVER_RECENT_MS;
  section.append(m.last_takeover
    ? northLine(`last session takeover: ${when(m.last_takeover)} (${m.session_takeovers} in all) — another client uses this client id`, recent)
    : northLine('last session takeover: none'));
  return section;
}

// Sparkplug B (SPEC §16): the edge node's session, what it sent, the commands it took.
function sparkplugSection(p) {
  const section = element('div', { 'data-section': 'sparkplug', 'data-connected': String(p.connected), 'data-born': String(p.born) });
  section.append(element('h4', {}, `Sparkplug: ${p.group_id}/${p.edge_node_id}`));
  const host = p.primary_host;
  if (!p.connected)
    section.append(northLine(`not connected to ${p.broker} since ${when(p.since)}` + (p.last_error ? `: ${p.last_error}` : ''), true));
  else if (p.born)
    section.append(northLine(`connected to ${p.broker} and born since ${when(p.since)}`));
  else
    section.append(northLine(`connected to ${p.broker} since ${when(p.since)}, not born` +
                             (host ? `: the births wait for the primary host ${host.name}` : ''), true));
  section.append(northLine(`bdSeq ${p.bdSeq === null ? 'none' : p.bdSeq}, next seq ${p.seq}; ${p.births} births, ${p.data} data sent`));
  const c = p.commands;
  section.append(northLine(`commands: ${c.taken} taken, ${c.refused} refused, ${c.malformed} malformed`, c.refused + c.malformed > 0));
  if (host) section.append(northLine(`primary host ${host.name}: ${host.state}`, host.state !== 'online'));
  return section;
}

// The northbound box: only the sections the config has.
function showNorth(panel) {
  const box = document.getElementById('north');
  const sections = [];
  if (panel.mqtt) sections.push(mqttSection(panel.mqtt));
  if (panel.sparkplug) sections.push(sparkplugSection(panel.sparkplug));
  box.hidden = sections.length === 0;
  box.replaceChildren(element('h3', {}, 'Northbound'), ...sections);
}

// The Config box (docs/fleet.md, "On the page"): the config in force and how the last change
// ended, the configs kept, a diff of the last change (for who may see the text: it may hold
// passwords), and for a user whom remote_config.http lists a form to apply a file or go back
// to the operator's file. /api/config says all of it, for the user who asks; the panel says
// when to ask again (its "config" changes with every change, by whatever channel).
const DIFF_CONTEXT = 3;              // unchanged lines around a change, as `diff -u`
const DIFF_MAX_CELLS = 1000 * 1000;  // the LCS table beyond the common start and end: 2 MB, some ms
let configKey = null;                // the panel's "config" last asked about
let configChanging = false;          // a PUT or POST is waiting for its answer
let configAnswers = 0;               // answers shown: the answer box's data-seq

const short = sha => (sha || '').slice(0, 12);
const resultClass = result => ({ applied: 'good', refused: 'bad', rolled_back: 'bad', busy: 'wait' })[result] || '';

// A text's lines, a final line end not making an empty last line.
const linesOf = text => text === '' ? [] : (text.endsWith('\n') ? text.slice(0, -1) : text).split('\n');

// The lines of `after` against `before`: [{kind: ' '|'-'|'+', text, old, new}], the line
// numbers 1-based (0 where the line is not on that side); null when the part that differs
// needs more than DIFF_MAX_CELLS to compare (a longest common subsequence, bounded work).
function lineDiff(before, after) {
  const a = linesOf(before), b = linesOf(after);
  let start = 0;
  while (start < a.length && start < b.length && a[start] === b[start]) start++;
  let endA = a.length, endB = b.length;
  while (endA > start && endB > start && a[endA - 1] === b[endB - 1]) { endA--; endB--; }
  const n = endA - start, m = endB - start;
  if (n * m > DIFF_MAX_CELLS) return null;
  const width = m + 1;
  const lcs = new Uint16Array((n + 1) * width);  // n·m ≤ 10^6: the shorter side, so the length, ≤ 1000
  for (let i = n - 1; i >= 0; i--)
    for (let j = m - 1; j >= 0; j--)
      lcs[i * width + j] = a[start + i] === b[start + j] ? lcs[(i + 1) * width + j + 1] + 1
                                                         : Math.max(lcs[(i + 1) * width + j], lcs[i * width + j + 1]);
  const ops = [];
  for (let k = 0; k < start; k++) ops.push({ kind: ' ', text: a[k], old: k + 1, new: k + 1 });
  let i = 0, j = 0;
  while (i < n || j < m) {
    if (i < n && j < m && a[start + i] === b[start + j]) {
      ops.push({ kind: ' ', text: a[start + i], old: start + i + 1, new: start + j + 1 }); i++; j++;
    } else if (i < n && (j === m || lcs[(i + 1) * width + j] >= lcs[i * width + j + 1])) {
      ops.push({ kind: '-', text: a[start + i], old: start + i + 1, new: 0 }); i++;  // removed before added, as diff -u
    } else {
      ops.push({ kind: '+', text: b[start + j], old: 0, new: start + j + 1 }); j++;
    }
  }
  for (let k = 0; endA + k < a.length; k++) ops.push({ kind: ' ', text: a[endA + k], old: endA + k + 1, new: endB + k + 1 });
  return ops;
}

// The changed lines with DIFF_CONTEXT lines around them, in hunks headed "@@ -3,7 +3,7 @@".
function unifiedHunks(ops) {
  const keep = ops.map(() => false);
  ops.forEach((op, k) => {
    if (op.kind === ' ') return;
    for (let c = Math.max(0, k - DIFF_CONTEXT); c <= Math.min(ops.length - 1, k + DIFF_CONTEXT); c++) keep[c] = true;
  });
  const lines = [];
  for (let k = 0; k < ops.length;) {
    if (!keep[k]) { k++; continue; }
    let end = k;
    while (end < ops.length && keep[end]) end++;
    const hunk = ops.slice(k, end);
    const olds = hunk.filter(op => op.kind !== '+'), news = hunk.filter(op => op.kind !== '-');
    const from = (side, key) => side.length ? side[0][key] : Math.max(0, (hunk.find(op => op[key]) || { [key]: 1 })[key] - 1);
    lines.push({ kind: '@', text: `@@ -${from(olds, 'old')},${olds.length} +${from(news, 'new')},${news.length} @@` });
    for (const op of hunk) lines.push({ kind: op.kind, text: op.kind + op.text });
    k = end;
  }
  return lines;
}

function configLine(text, attributes = {}) { return element('p', attributes, text); }

function inForceLines(c) {
  const sha = element('span', { class: 'sha', title: c.sha256 }, short(c.sha256));
  const what = configLine(`${c.source === 'file' ? "the operator's file" : `from ${c.source}`} ${c.file}, sha256 `, { 'data-field': 'in-force' });
  what.append(sha);
  if (c.number !== null && c.number !== undefined) what.append(`, remote config ${c.number} by ${c.by}, applied ${when(c.applied_at)}`);
  const lines = [what];
  const last = c.last;
  lines.push(last
    ? configLine(`last change: ${last.result}${last.reason ? ` — ${last.reason}` : ''} (${last.source} by ${last.by}, ${when(last.at)})`,
                 { 'data-field': 'last', 'data-result': last.result, class: resultClass(last.result) })
    : configLine('last change: none since the start', { 'data-field': 'last' }));
  return lines;
}

function historyTable(history) {
  if (!history.length) return [configLine('history: no config from afar is kept')];
  const table = element('table', { class: 'history' });
  const head = element('tr');
  for (const name of ['number', 'source', 'by', 'applied', '']) head.append(element('th', {}, name));
  table.append(head);
  for (const h of history) {
    const tr = element('tr', { 'data-number': String(h.number), 'data-in-force': String(h.in_force) });
    tr.append(element('td', { class: 'count' }, String(h.number)), element('td', {}, h.source), element('td', {}, h.by),
              element('td', {}, when(h.applied_at)), element('td', {}, h.in_force ? 'in force' : ''));
    table.append(tr);
  }
  return [element('h3', {}, `History (the last ${history.length} kept)`), table];
}

// The diff of the last change: what it replaced (a kept config, or the operator's file)
// against what is in force.
function diffBox(inForce) {
  const replaced = inForce.replaced;
  const title = element('h3', {}, 'Last change');
  if (!replaced) return [title, configLine('nothing to compare: no change since the start', { 'data-field': 'diff-none' })];
  const before = replaced.number === null ? "the operator's file" : `remote config ${replaced.number}`;
  title.textContent = `Last change: ${before} → the config in force`;
  if (typeof replaced.text !== 'string' || typeof inForce.text !== 'string')
    return [title, configLine(`cannot compare: ${replaced.text_error || inForce.text_error || 'a text is missing'}`, { 'data-field': 'diff-none' })];
  const ops = lineDiff(replaced.text, inForce.text);
  if (!ops) return [title, configLine('too many changes to show', { 'data-field': 'diff-none' })];
  const hunks = unifiedHunks(ops);
  if (!hunks.length) return [title, configLine('the texts are the same', { 'data-field': 'diff-none' })];
  const pre = element('pre', { class: 'diff' });
  for (const line of hunks) pre.append(element('span', { class: 'diff-line', 'data-kind': line.kind }, line.text + '\n'));
  return [title, pre];
}

function showConfig(shown) {
  const box = document.getElementById('config');
  const c = shown.in_force;
  // A bridge that takes no config from afar and never did has nothing to show here.
  box.hidden = !(shown.takes_changes_from_afar || c.source !== 'file' || shown.history.length > 0 || c.last);
  box.dataset.source = c.source;
  box.dataset.mayChange = String(shown.may_change);
  document.getElementById('config-in-force').replaceChildren(...inForceLines(c));
  document.getElementById('config-history').replaceChildren(...historyTable(shown.history));
  const diff = document.getElementById('config-diff');
  diff.hidden = !shown.may_change;  // the texts: only for who may change them
  diff.replaceChildren(...(shown.may_change ? diffBox(c) : []));
  document.getElementById('config-form').hidden = !shown.may_change;
  box.dataset.loaded = String(Number(box.dataset.loaded || 0) + 1);
}

async function loadConfig() {
  const answer = await fetch(api('/api/config'));
  if (!answer.ok) {  // 503: this daemon takes no config changes
    document.getElementById('config').hidden = true;
    return;
  }
  showConfig(await answer.json());
}

function showConfigChanged(panelConfig) {
  const key = JSON.stringify(panelConfig || null);
  if (key === configKey || configChanging) return;
  configKey = key;
  loadConfig().catch(() => {});
}

// The answer of PUT /api/config or POST /api/config/revert: its result and reason, every
// error at its line and column; or why the server would not (403, 401, 413).
function showAnswer(what, status, body) {
  const box = document.getElementById('config-answer');
  box.hidden = false;
  box.dataset.state = 'answered';
  box.dataset.result = body.result || 'not done';
  box.className = resultClass(body.result) || 'bad';
  const lines = [configLine(`${what}: ` + (body.result ? `${body.result}${body.reason ? ' — ' + body.reason : ''}` : `not done (HTTP ${status}): ${body.error || ''}`),
                            { 'data-field': 'result' })];
  if (body.errors && body.errors.length) {
    const list = element('ul', { class: 'errors' });
    for (const e of body.errors) list.append(element('li', {}, `${e.line}:${e.column}: ${e.message}`));
    lines.push(list);
  }
  box.replaceChildren(...lines);
}

async function changeConfig(what, request) {
  const form = document.getElementById('config-form');
  const box = document.getElementById('config-answer');
  for (const button of form.querySelectorAll('button')) button.disabled = true;
  configChanging = true;
  const seq = String(++configAnswers);
  box.dataset.seq = seq;
  box.hidden = false;
  box.dataset.state = 'waiting';
  delete box.dataset.result;
  box.className = 'wait';
  box.replaceChildren(configLine(`${what}: waiting for the answer — it comes once the new config has passed its probe (remote_config.probe) or failed`));
  try {
    const answer = await request();
    const body = await answer.json().catch(() => ({}));
    showAnswer(what, answer.status, body);
  } catch (error) {
    showAnswer(what, 0, { error: String(error) });
  } finally {
    for (const button of form.querySelectorAll('button')) button.disabled = false;
    configChanging = false;
    await loadConfig().catch(() => {});
    box.dataset.refreshed = seq;  // the box shows what the answer left in force
  }
}

document.getElementById('config-form').addEventListener('submit', async e => {
  e.preventDefault();
  const file = e.target.elements.file.files[0];
  if (!file) return showAnswer('apply', 0, { error: 'choose a config file first' });
  const text = await file.text();
  changeConfig(`applying ${file.name}`, () => fetch(api('/api/config'), { method: 'PUT', body: text, headers: { 'Content-Type': 'application/yaml' } }));
});

document.querySelector('#config-form [data-action="revert"]').addEventListener('click', () => {
  if (!confirm("Go back to the operator's file? The config from afar in force stops, and stays kept in the history.")) return;
  changeConfig("going back to the operator's file", () => fetch(api('/api/config/revert'), { method: 'POST' }));
});

function showPanel(panel) {
  document.getElementById('mode').textContent = `${panel.mode} mode`;
  showLed('led-modbus', panel.modbus);
  showLed('led-unimabus', panel.unimabus);
  document.getElementById('led-error').dataset.on = String(panel.error);
  document.getElementById('devices').replaceChildren(...panel.devices.map(d => chip(d.bank, d.type, d.online, d.type !== null)));
  document.getElementById('modules').replaceChildren(...panel.modules.map(m => chip(m.bank, null, m.online)));
  document.getElementById('indicators').replaceChildren(...panel.indicators.map(indicatorBox));
  showSerialLines(panel.serial_lines);
  showGateway(panel.gateway);
  showNorth(panel);
  showConfigChanged(panel.config);
}

// A monitor line by its transaction's state (Done, Not4Me, Err01…Err04, Timeout, Cached),
// which the stylesheet colours: an Err02 must not look like a Done.
function monitorLine(text, state) {
  const line = element('div', { class: 'line' }, text);
  const found = state || (/(?:^| )State=(\w+)/.exec(text) || [])[1];
  if (found) line.dataset.state = found;
  return line;
}

function showLines(event) {
  const box = document.getElementById('lines');
  const atBottom = box.scrollTop + box.clientHeight >= box.scrollHeight - 4;
  if (event.skipped > 0) box.append(monitorLine(`… ${event.skipped} more transactions passed the filter`, 'skipped'));
  for (const text of event.lines) box.append(monitorLine(text));
  while (box.childElementCount > MAX_LINES) box.firstElementChild.remove();
  if (atBottom) box.scrollTop = box.scrollHeight;
}

function filterQuery() {
  const form = new FormData(document.getElementById('filter'));
  return new URLSearchParams([...form.entries()].map(([k, v]) => [k, String(v).trim() || 'xx'])).toString();
}

function setFeed(state, text) {
  const feed = document.getElementById('feed');
  feed.dataset.state = state;
  feed.textContent = text;
}

function connect() {
  if (source) source.close();
  document.getElementById('lines').replaceChildren();
  source = new EventSource(api('/api/events?' + filterQuery()));
  let lost = false;
  source.onopen = () => {
    // Back after a restart or a reload of the daemon: its register map may differ.
    if (lost) return loadLayout().then(connect);
    setFeed('live', 'live');
  };
  source.onerror = () => {  // EventSource tries again by itself
    lost = true;
    setFeed('lost', 'reconnecting…');
  };
  source.addEventListener('panel', e => showPanel(JSON.parse(e.data)));
  source.addEventListener('registers', e => {
    for (const [address, raw] of Object.entries(JSON.parse(e.data))) setRaw(address, raw);
  });
  source.addEventListener('values', e => {
    for (const [key, value] of Object.entries(JSON.parse(e.data))) setValue(key, value);
  });
  source.addEventListener('monitor', e => showLines(JSON.parse(e.data)));
  // The map changed (a reload): build it again, then a new stream's full picture fills it.
  source.addEventListener('layout', () => loadLayout().then(connect));
}

async function checkFilter() {
  const answer = await fetch(api('/api/events?' + filterQuery()), { method: 'HEAD' });
  document.getElementById('filter-error').textContent = answer.ok ? '' : 'not a filter: ad and fn are xx or 0..255, from and to 0x0000..0xFFFF';
  return answer.ok;
}

async function loadLayout() {
  const answer = await fetch(api('/api/registers'));
  buildBanks(await answer.json());
}

document.getElementById('filter').addEventListener('submit', async e => {
  e.preventDefault();
  if (await checkFilter()) connect();
});

loadLayout().then(connect, error => setFeed('lost', `cannot load the register map: ${error}`));
