#!/usr/bin/env python3
"""Opens the daemon's front page in headless Chromium (Debian's chromium and
chromium-driver, driven over WebDriver with nothing but the standard library) and waits
until the DOM shows what the test expects: register values (by the raw value of their
cell) and devices on line. Used by tests/integration/browser_test.cpp and for the
screenshot in docs/.

  page_in_chromium.py --url http://127.0.0.1:8080/ [--expect 0x0012=1234 ...] [--online D1 ...]
                      [--indicator 1=write ...] [--ready-file F --then 0x0012=4321 ...]
                      [--gateway 7="not answering" ...] [--north mqtt="not connected" ...]
                      [--serial-line scada="19200 8E1" ...]
                      [--line Err02 ...] [--every-value] [--screenshot out.png] [--window 1200,1500]
                      [--timeout 20]

--indicator N=read|write: capture indicator N shows a value of that access.
--gateway UNIT=STATE: the gateway table's row of that unit is in that state ("answering",
"not answering"); the JSON line then holds every row (state, text, colour).

--north SECTION=TEXT: the northbound box's section ("mqtt", "sparkplug") shows TEXT; the
JSON line then holds every section (its text, and each line's text and colour).

--serial-line NAME=TEXT: the RS-485 line NAME's box shows TEXT; the JSON line then holds
every line's box (text, open, each paragraph's text and colour).

--config-box: also awaits the Config box, loaded (and holding every --config-expect TEXT);
the JSON line then holds it as "config": shown or hidden, its source, whether the user may
change it, each line (text, colour), the history rows, the diff's lines (kind, text,
colour) and the form. --apply-file FILE (repeatable, in order) then chooses FILE in the
box's form and presses Apply, --revert (after them) presses "Revert to the operator's file"
and accepts its confirmation; each waits for the answer and the box refreshed, and the JSON
line's "steps" holds, per step, the states the answer went through (each with whether the
buttons were off), the answer, and the box then.
--ignore-certificate-errors: for HTTPS with the test's own CA (--url https://name:pw@…/).

--ready-file: written once the first expectations hold; the --then expectations are
awaited after it (the test feeds them a moment after the page showed the first ones).
--line STATE: with --ready-file, also awaited after it: the monitor box shows a line of
that state; the JSON line then holds every monitor line (state, colour, whether it is cut
at the box's edge) and how many of the table's labels are visible.
The window is --window (e.g. 390,844 for a phone); Chromium's language is en-US, so numbers
are grouped as "41,234".
--every-value: the JSON line also holds every value cell by its key ("D1/engine_speed":
its text, state and address) and the capture indicators (access, class, colour).
Prints one JSON line with what the page showed; exits 1 when an expectation did not hold.
"""
import argparse
import base64
import json
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

CHROMIUM_FLAGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync", "--lang=en-US",
]

READ_PAGE = """
const result = { values: {}, online: {}, feed: document.getElementById('feed').dataset.state };
for (const cell of document.querySelectorAll('td.value[data-address]'))
  result.values[cell.dataset.address] = { raw: cell.dataset.raw, text: cell.textContent };
for (const chip of document.querySelectorAll('#devices .chip'))
  result.online[chip.dataset.bank] = chip.dataset.online === 'true';
result.error_led = document.getElementById('led-error').dataset.on === 'true';
result.keys = {};
for (const cell of document.querySelectorAll('td.value[data-key]'))
  result.keys[cell.dataset.key] = { text: cell.textContent, state: cell.dataset.state, address: cell.dataset.address, title: cell.title };
result.indicators = [...document.querySelectorAll('#indicators .indicator')].map(box => {
  const value = box.querySelector('.value');
  return { access: box.dataset.access || null, class: box.className, text: value ? value.textContent : null,
           colour: value ? getComputedStyle(value).color : null };
});
result.gateway = {};
for (const row of document.querySelectorAll('#gateway tr[data-unit]'))
  result.gateway[row.dataset.unit] = { state: row.dataset.state, text: row.textContent,
                                       colour: getComputedStyle(row.querySelector('td.state')).color };
result.serial_lines = {};
for (const box of document.querySelectorAll('#serial-lines:not([hidden]) [data-line]'))
  result.serial_lines[box.dataset.line] = {
    text: box.textContent, open: box.dataset.open,
    lines: [...box.querySelectorAll('p')].map(p => ({ text: p.textContent, colour: getComputedStyle(p).color })) };
result.north = {};
for (const section of document.querySelectorAll('#north:not([hidden]) [data-section]'))
  result.north[section.dataset.section] = {
    text: section.textContent, connected: section.dataset.connected,
    lines: [...section.querySelectorAll('p')].map(p => ({ text: p.textContent, colour: getComputedStyle(p).color })) };
const lines = document.getElementById('lines');
result.monitor = [...lines.querySelectorAll('.line')].map(line => ({
  text: line.textContent, state: line.dataset.state || null, colour: getComputedStyle(line).color }));
result.monitor_cut = lines.scrollWidth > lines.clientWidth;
const labels = [...document.querySelectorAll('td.label')];
result.labels = { all: labels.length, shown: labels.filter(td => td.offsetWidth > 0 && td.textContent).length,
                  with_text: labels.filter(td => td.textContent).length };
result.width = document.documentElement.clientWidth;
return result;
"""

READ_CONFIG = """
const box = document.getElementById('config');
const colour = e => getComputedStyle(e).color;
const answer = document.getElementById('config-answer');
const diff = document.getElementById('config-diff');
const form = document.getElementById('config-form');
return {
  hidden: box.hidden, loaded: Number(box.dataset.loaded || 0), source: box.dataset.source || null,
  may_change: box.dataset.mayChange === 'true', text: box.textContent,
  lines: [...box.querySelectorAll('#config-in-force p')].map(p => ({ field: p.dataset.field, result: p.dataset.result || null,
                                                                    text: p.textContent, colour: colour(p), title: (p.querySelector('.sha') || {}).title || null })),
  history: [...box.querySelectorAll('#config-history tr[data-number]')].map(tr => ({
    number: Number(tr.dataset.number), in_force: tr.dataset.inForce === 'true', text: tr.textContent })),
  diff: { shown: !diff.hidden, text: diff.textContent,
          lines: [...diff.querySelectorAll('.diff-line')].map(l => ({ kind: l.dataset.kind, text: l.textContent.replace(/\\n$/, ''), colour: colour(l) })) },
  form: { shown: !form.hidden, disabled: [...form.querySelectorAll('button')].some(b => b.disabled) },
  answer: { shown: !answer.hidden, state: answer.dataset.state, result: answer.dataset.result || null, text: answer.textContent,
            seq: Number(answer.dataset.seq || 0), refreshed: Number(answer.dataset.refreshed || 0),
            colour: colour(answer), errors: [...answer.querySelectorAll('li')].map(li => li.textContent) },
};
"""


# Records each state the answer box goes through, and whether the buttons were off then:
# the answer may come before the next look (a probe passes as soon as everything holds).
WATCH_ANSWER = """
const answer = document.getElementById('config-answer');
const form = document.getElementById('config-form');
window.configStates = [];
if (!window.configWatch) {
  window.configWatch = new MutationObserver(() => window.configStates.push({
    state: answer.dataset.state, text: answer.textContent, disabled: [...form.querySelectorAll('button')].every(b => b.disabled) }));
  window.configWatch.observe(answer, { attributes: true, attributeFilter: ['data-state'] });
}
"""


def element_id(found):
    """The id of an element WebDriver found (W3C's web element identifier)."""
    return found["element-6066-11e4-a52e-4f735466cecf"]


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def call(base, method, path, body=None):
    data = None if body is None else json.dumps(body).encode()
    request = urllib.request.Request(base + path, data=data, method=method,
                                     headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=30) as answer:
        return json.load(answer)["value"]


def parse_expectations(items):
    expected = {}
    for item in items:
        address, value = item.split("=", 1)
        expected[address.upper().replace("0X", "0x")] = str(int(value, 0))
    return expected


def parse_indicators(items):
    return {int(number): access for number, access in (item.split("=", 1) for item in items)}


def parse_gateway(items):
    return dict(item.split("=", 1) for item in items)


def holds(page, values, online, indicators={}, gateway={}, north=[], lines=[], serial_lines=[]):
    shown = page.get("indicators", [])
    states = {line["state"] for line in page.get("monitor", [])}
    rows = page.get("gateway", {})
    sections = page.get("north", {})
    boxes = page.get("serial_lines", {})
    return (all(text in boxes.get(name, {}).get("text", "") for name, text in serial_lines) and all(page["values"].get(a, {}).get("raw") == v for a, v in values.items())
            and all(page["online"].get(bank) for bank in online)
            and all(n <= len(shown) and shown[n - 1]["access"] == access for n, access in indicators.items())
            and all(rows.get(unit, {}).get("state") == state for unit, state in gateway.items())
            and all(text in sections.get(section, {}).get("text", "") for section, text in north)
            and all(state in states for state in lines))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--url", required=True)
    parser.add_argument("--expect", action="append", default=[])
    parser.add_argument("--online", action="append", default=[])
    parser.add_argument("--ready-file")
    parser.add_argument("--then", action="append", default=[])
    parser.add_argument("--indicator", action="append", default=[])
    parser.add_argument("--gateway", action="append", default=[])
    parser.add_argument("--north", action="append", default=[])
    parser.add_argument("--serial-line", action="append", default=[])
    parser.add_argument("--line", action="append", default=[])
    parser.add_argument("--every-value", action="store_true")
    parser.add_argument("--config-box", action="store_true")
    parser.add_argument("--config-expect", action="append", default=[])
    parser.add_argument("--apply-file", action="append", default=[])
    parser.add_argument("--revert", action="store_true")
    parser.add_argument("--ignore-certificate-errors", action="store_true")
    parser.add_argument("--screenshot")
    parser.add_argument("--window", default="1200,1500", help="width,height of the window")
    parser.add_argument("--timeout", type=float, default=20)
    args = parser.parse_args()

    port = free_port()
    profile = tempfile.mkdtemp(prefix="unima-chromium-")
    driver = subprocess.Popen(["chromedriver", f"--port={port}"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    base = f"http://127.0.0.1:{port}"
    session = None
    page = {}
    try:
        deadline = time.monotonic() + 10
        while True:
            try:
                urllib.request.urlopen(base + "/status", timeout=1).read()
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)
        flags = CHROMIUM_FLAGS + (["--ignore-certificate-errors"] if args.ignore_certificate_errors else [])
        options = {"binary": "/usr/bin/chromium", "args": flags + [f"--window-size={args.window}", f"--user-data-dir={profile}"]}
        width, height = (int(n) for n in args.window.split(","))
        if width < 500:  # headless Chromium's window is never narrower: a phone's width is emulated
            options["mobileEmulation"] = {"deviceMetrics": {"width": width, "height": height, "pixelRatio": 3}}
        capabilities = {"capabilities": {"alwaysMatch": {"browserName": "chrome", "goog:chromeOptions": options}}}
        session = call(base, "POST", "/session", capabilities)["sessionId"]
        call(base, "POST", f"/session/{session}/url", {"url": args.url})

        def wait_for(values, online, indicators={}, gateway={}, north=[], lines=[], serial_lines=[]):
            nonlocal page
            deadline = time.monotonic() + args.timeout
            while True:
                page = call(base, "POST", f"/session/{session}/execute/sync", {"script": READ_PAGE, "args": []})
                if holds(page, values, online, indicators, gateway, north, lines, serial_lines):
                    return True
                if time.monotonic() > deadline:
                    return False
                time.sleep(0.1)

        ok = wait_for(parse_expectations(args.expect), args.online, parse_indicators(args.indicator),
                      parse_gateway(args.gateway), [tuple(item.split("=", 1)) for item in args.north],
                      serial_lines=[tuple(item.split("=", 1)) for item in args.serial_line])
        config = {}
        first = {}
        steps = []

        def read_config():
            return call(base, "POST", f"/session/{session}/execute/sync", {"script": READ_CONFIG, "args": []})

        def wait_for_config(check):
            nonlocal config
            deadline = time.monotonic() + args.timeout
            while True:
                config = read_config()
                if check(config):
                    return True
                if time.monotonic() > deadline:
                    return False
                time.sleep(0.1)

        def click(selector):
            found = call(base, "POST", f"/session/{session}/element", {"using": "css selector", "value": selector})
            call(base, "POST", f"/session/{session}/element/{element_id(found)}/click", {})

        def change(action, what, start):
            seq = config["answer"]["seq"]
            call(base, "POST", f"/session/{session}/execute/sync", {"script": WATCH_ANSWER, "args": []})
            start()
            if action == "revert":  # its confirmation: nothing else runs while it is open
                deadline = time.monotonic() + args.timeout
                while True:
                    try:
                        call(base, "POST", f"/session/{session}/alert/accept", {})
                        break
                    except OSError:
                        if time.monotonic() > deadline:
                            raise
                        time.sleep(0.05)
            done = wait_for_config(lambda c: c["answer"]["seq"] > seq and c["answer"]["refreshed"] == c["answer"]["seq"])
            states = call(base, "POST", f"/session/{session}/execute/sync", {"script": "return window.configStates", "args": []})
            steps.append({"action": action, "what": what, "done": done, "states": states, "answer": config["answer"], "config": config})
            return done

        if ok and args.config_box:
            ok = wait_for_config(lambda c: c["loaded"] > 0 and all(t in c["text"] for t in args.config_expect))
            first = config
            for path in args.apply_file:
                if not ok:
                    break

                def choose_and_apply(path=path):
                    found = call(base, "POST", f"/session/{session}/element",
                                 {"using": "css selector", "value": "#config-form input[type=file]"})
                    call(base, "POST", f"/session/{session}/element/{element_id(found)}/value", {"text": os.path.abspath(path)})
                    click('#config-form button[data-action="apply"]')

                ok = change("apply", path, choose_and_apply)
            if ok and args.revert:
                ok = change("revert", "revert", lambda: click('#config-form button[data-action="revert"]'))
        if ok and args.ready_file:
            with open(args.ready_file, "w") as f:
                f.write("ready\n")
            ok = wait_for(parse_expectations(args.then), args.online, lines=args.line)
        if args.screenshot:
            time.sleep(1)  # the cells' flash of a change fades
            png = base64.b64decode(call(base, "GET", f"/session/{session}/screenshot"))
            with open(args.screenshot, "wb") as f:
                f.write(png)
        shown = {a: page["values"].get(a.upper().replace("0X", "0x"))
                 for a in [e.split("=")[0] for e in args.expect + args.then]}
        report = {"ok": ok, "feed": page.get("feed"), "online": page.get("online"), "values": shown,
                  "cells": len(page.get("values", {}))}
        if args.gateway:
            report.update(gateway=page.get("gateway", {}))
        if args.north:
            report.update(north=page.get("north", {}))
        if args.serial_line:
            report.update(serial_lines=page.get("serial_lines", {}))
        if args.line:
            report.update(monitor=page.get("monitor", []), monitor_cut=page.get("monitor_cut"), labels=page.get("labels"),
                          width=page.get("width"))
        if args.config_box:
            report.update(first=first, config=config, steps=steps)
        if args.every_value:
            report.update(keys=page.get("keys", {}), indicators=page.get("indicators", []),
                          addresses=sorted(page.get("values", {})))
        print(json.dumps(report))
        return 0 if ok else 1
    finally:
        if session:
            try:
                call(base, "DELETE", f"/session/{session}")
            except OSError:
                pass
        driver.terminate()
        driver.wait(10)
        shutil.rmtree(profile, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
