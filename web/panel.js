// The front page (SPEC §13): the register map once from /api/registers, then everything
// live from /api/events (app/live_view.hpp): a full picture on connecting, changes after.
'use strict';

const NOT_MEASURED = 0x7FFF;  // seed 004: a value the device does not measure
const MAX_LINES = 200;
const cells = new Map();      // "0x1100" -> { cell, row }
let source = null;

const element = (tag, attributes = {}, text) => {
  const e = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes)) e.setAttribute(name, value);
  if (text !== undefined) e.textContent = text;
  return e;
};

function shown(row, raw) {
  if (raw === null || raw === undefined) return { text: '—', measured: true };
  if (raw === NOT_MEASURED && row.kind === 'analog') return { text: 'not measured', measured: false };
  if (row.kind === 'bits') return { text: '0x' + raw.toString(16).toUpperCase().padStart(4, '0'), measured: true };
  if (row.kind === 'analog') {
    const signed = raw >= 0x8000 ? raw - 0x10000 : raw;
    const digits = row.scale < 1 ? Math.round(-Math.log10(row.scale)) : 0;
    return { text: (signed * row.scale).toFixed(digits) + (row.unit ? ' ' + row.unit : ''), measured: true };
  }
  return { text: String(raw) + (row.unit ? ' ' + row.unit : ''), measured: true };
}

function buildBanks(rows) {
  const banks = document.getElementById('banks');
  banks.replaceChildren(element('h2', {}, 'Banks'));
  cells.clear();
  const byBank = new Map();
  for (const row of rows) {
    if (!byBank.has(row.bank)) byBank.set(row.bank, []);
    byBank.get(row.bank).push(row);
  }
  for (const [bank, bankRows] of byBank) {
    const details = element('details', { class: 'bank', 'data-bank': bank });
    details.open = byBank.size <= 4 || bank.startsWith('D');
    details.append(element('summary', {}, `${bank} — ${bankRows.length} registers from ${bankRows[0].address}`));
    const table = element('table');
    const head = element('tr');
    for (const [name, cls] of [['address', 'address'], ['name', ''], ['label', 'label'], ['value', '']]) head.append(element('th', cls ? { class: cls } : {}, name));
    table.append(head);
    for (const row of bankRows) {
      const tr = element('tr');
      const cell = element('td', { class: 'value', 'data-address': row.address });
      tr.append(element('td', { class: 'address' }, row.address), element('td', {}, row.id),
                element('td', { class: 'label', lang: 'cs' }, row.label), cell);
      table.append(tr);
      cells.set(row.address, { cell, row });
      setValue(row.address, row.value, false);
    }
    details.append(table);
    banks.append(details);
  }
}

function setValue(address, raw, flash = true) {
  const entry = cells.get(address);
  if (!entry) return;
  const { text, measured } = shown(entry.row, raw);
  entry.cell.textContent = text;
  entry.cell.dataset.raw = raw === null ? '' : String(raw);
  entry.cell.dataset.measured = String(measured);
  if (flash) {
    entry.cell.classList.add('changed');
    setTimeout(() => entry.cell.classList.remove('changed'), 50);
  }
}

function chip(bank, type, online, configured = true) {
  return element('span', { class: 'chip', 'data-bank': bank, 'data-online': String(online), 'data-configured': String(configured),
                           title: type || 'not configured' }, type ? `${bank} ${type}` : bank);
}

function showPanel(panel) {
  document.getElementById('mode').textContent = `${panel.mode} mode`;
  document.getElementById('led-modbus').dataset.on = String(panel.modbus);
  document.getElementById('led-unimabus').dataset.on = String(panel.unimabus);
  document.getElementById('led-error').dataset.on = String(panel.error);
  document.getElementById('devices').replaceChildren(...panel.devices.map(d => chip(d.bank, d.type, d.online, d.type !== null)));
  document.getElementById('modules').replaceChildren(...panel.modules.map(m => chip(m.bank, null, m.online)));
  document.getElementById('indicators').replaceChildren(...panel.indicators.map((indicator, i) => {
    const box = element('div', { class: 'indicator', 'data-indicator': String(i + 1) });
    const value = indicator.value === null ? '—'
      : `0x${indicator.value.toString(16).toUpperCase().padStart(4, '0')} (${indicator.value})`;
    box.append(element('div', { class: 'what' }, `${i + 1}: ad ${indicator.address}, register 0x${indicator.register.toString(16).toUpperCase().padStart(4, '0')}`),
               element('div', { class: 'value' }, value),
               element('div', { class: 'what' }, indicator.access ? `${indicator.access} ${indicator.time}` : 'not seen'));
    return box;
  }));
}

function showLines(event) {
  const pre = document.getElementById('lines');
  const atBottom = pre.scrollTop + pre.clientHeight >= pre.scrollHeight - 4;
  let text = pre.textContent;
  if (event.skipped > 0) text += `… ${event.skipped} more transactions passed the filter\n`;
  for (const line of event.lines) text += line + '\n';
  const lines = text.split('\n');
  if (lines.length > MAX_LINES + 1) text = lines.slice(lines.length - MAX_LINES - 1).join('\n');
  pre.textContent = text;
  if (atBottom) pre.scrollTop = pre.scrollHeight;
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
  document.getElementById('lines').textContent = '';
  source = new EventSource('/api/events?' + filterQuery());
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
    for (const [address, raw] of Object.entries(JSON.parse(e.data))) setValue(address, raw);
  });
  source.addEventListener('monitor', e => showLines(JSON.parse(e.data)));
  // The map changed (a reload): build it again, then a new stream's full picture fills it.
  source.addEventListener('layout', () => loadLayout().then(connect));
}

async function checkFilter() {
  const answer = await fetch('/api/events?' + filterQuery(), { method: 'HEAD' });
  document.getElementById('filter-error').textContent = answer.ok ? '' : 'not a filter: ad and fn are xx or 0..255, from and to 0x0000..0xFFFF';
  return answer.ok;
}

async function loadLayout() {
  const answer = await fetch('/api/registers');
  buildBanks(await answer.json());
}

document.getElementById('filter').addEventListener('submit', async e => {
  e.preventDefault();
  if (await checkFilter()) connect();
});

loadLayout().then(connect, error => setFeed('lost', `cannot load the register map: ${error}`));
