#!/usr/bin/env python3
"""A man page and its program's --help name the same subcommands and options.

usage: man_vs_help.py PAGE PROGRAM

The program's --help is the reference: its usage lines (`usage: prog SUB [opts]`, one per
subcommand, and `prog --version | -h|--help`) name every subcommand and option; a
subcommand that answers --help itself must print the same usage line. The man page has a
`.SS "prog SUB"` under COMMANDS for each subcommand, with a `.TP` per option of it, and
the options of no subcommand as `.TP` under OPTIONS. Any difference either way fails, so
an option added to the program without its man page entry (or the reverse) is caught.
"""

import os
import re
import subprocess
import sys

OPTION = re.compile(r"(?<![\w-])--?[A-Za-z][\w-]*")


def usage_lines(program, *args):
    """The usage lines of `program args --help`, or [] when it does not answer --help."""
    run = subprocess.run([program, *args, "--help"], capture_output=True, text=True)
    if run.returncode != 0 or not run.stdout.startswith("usage:"):
        return []  # a subcommand without a --help of its own (tables prints its tables)
    lines = []
    for line in run.stdout.splitlines():
        if not line.strip():
            break
        lines.append(line.removeprefix("usage:").strip())
    return lines


def from_help(program):
    """{subcommand or None: set of options}, and the problems found on the way."""
    name = os.path.basename(program)
    found, problems = {}, []
    for line in usage_lines(program):
        words = line.split()
        if not words or words[0] != name:
            problems.append(f"--help: a usage line that does not start with {name}: {line!r}")
            continue
        rest = words[1:]
        sub = None if not rest or rest[0].startswith("-") else rest[0]
        found.setdefault(sub, set()).update(OPTION.findall(" ".join(rest[1:] if sub else rest)))
        if sub:
            own = usage_lines(program, sub)
            if own and own[0] != line:
                problems.append(f"{name} {sub} --help says {own[0]!r}, {name} --help says {line!r}")
    if not found:
        problems.append(f"{name} --help printed no usage line")
    return found, problems


def groff_text(line):
    line = line.replace("\\-", "-").replace('"', " ")
    return re.sub(r"\\f[BIRP]", "", line)


def from_man(page):
    """{subcommand or None: set of options in its .TP tags}."""
    found = {}
    section, sub, tag_next = None, None, False
    with open(page, encoding="utf-8") as source:
        for raw in source:
            line = groff_text(raw.rstrip("\n"))
            if line.startswith(".SH"):
                section, sub = line[3:].strip(), None
                if section == "OPTIONS":
                    found.setdefault(None, set())
            elif line.startswith(".SS") and section == "COMMANDS":
                sub = line[3:].split()[-1]
                found.setdefault(sub, set())
            elif line.startswith(".TP"):
                tag_next = True
                continue
            elif tag_next and (section == "OPTIONS" or (section == "COMMANDS" and sub)):
                found[sub if section == "COMMANDS" else None].update(OPTION.findall(line))
            tag_next = False
    return found


def main():
    page, program = sys.argv[1], sys.argv[2]
    helped, problems = from_help(program)
    documented = from_man(page)
    name = os.path.basename(page)
    for sub in sorted(set(helped) | set(documented), key=lambda s: s or ""):
        what = f"subcommand {sub}" if sub else "the options of no subcommand"
        if sub not in documented:
            problems.append(f"{name} does not describe {what} (no .SS under COMMANDS / OPTIONS)")
            continue
        if sub not in helped:
            problems.append(f"{name} describes {what}, which --help does not list")
            continue
        for option in sorted(helped[sub] - documented[sub]):
            problems.append(f"{name}: {what}: {option} is in --help but has no .TP entry")
        for option in sorted(documented[sub] - helped[sub]):
            problems.append(f"{name}: {what}: {option} has a .TP entry but is not in --help")
    for problem in problems:
        print(f"FAIL: {problem}", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
