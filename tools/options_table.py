#!/usr/bin/env python3
"""Prints a markdown table of every field of every `struct *Options` in lib/mesohex/**/*.h: parameter, default, and the
header's comment on it (meaning and unit). docs/tuning.md's parameter table is this output plus a fourth column, the
measurement history, written by hand.

  tools/options_table.py [lib-dir]                  print the three-column table
  tools/options_table.py --update docs/tuning.md    rewrite the doc's table: every parameter in header order, the
                                                    first three columns regenerated, each row's fourth column kept
  tools/options_table.py --check docs/tuning.md     exit 1 (listing them) if a parameter is missing from the doc's
                                                    table, listed there but gone, or its default / meaning is stale
"""
import os
import re
import sys

FIELD = re.compile(r'^(\s*)([A-Za-z_][\w:<>, ()&*]*?[\w>])\s+([a-z_][\w]*)(\s*=\s*([^;]*))?;\s*(//\s*(.*))?$')


def fields(text):
    out = []
    for m in re.finditer(r'struct\s+(\w*Options)\s*\{', text):
        name, i, depth = m.group(1), m.end(), 1
        j = i
        while depth and j < len(text):
            depth += {'{': 1, '}': -1}.get(text[j], 0)
            j += 1
        pending, last, body = [], None, text[i:j - 1]
        for line in body.splitlines():
            s = line.strip()
            if not s:
                pending = []
                continue
            if s.startswith('//'):
                c = s[2:].strip()
                # A comment indented beyond the field column continues the field above it.
                if last is not None and len(line) - len(line.lstrip()) > 8 and not pending:
                    last[3].append(c)
                else:
                    pending.append(c)
                continue
            f = FIELD.match(line)
            if f and ('(' not in f.group(2) or '<' in f.group(2)) and f.group(2) not in ('return', 'using'):
                comment = pending + ([f.group(7)] if f.group(7) else [])
                last = [name, f.group(3), (f.group(5) or '{}').strip(), comment]
                out.append(last)
            pending = []
    return out


def rows(root):
    """(parameter, default, meaning) of every options field under root, in header order."""
    out = []
    for d, _, names in sorted(os.walk(root)):
        for n in sorted(names):
            if not n.endswith('.h'):
                continue
            for struct, field, default, comment in fields(open(os.path.join(d, n)).read()):
                text = ' '.join(comment).replace('|', '\\|')
                out.append((f'`{struct}::{field}`', f'`{default}`', text))
    return out


TABLE_HEAD = '| Parameter | Default | Meaning, unit, what it protects | How it was measured |'
CELL = re.compile(r'(?<!\\)\|')


def doc_table(lines):
    """(first, last) line indices of the doc's parameter table body, and {parameter: cells} of its rows."""
    head = lines.index(TABLE_HEAD)
    first = head + 2
    last = first
    while last < len(lines) and lines[last].startswith('|'):
        last += 1
    cells = {}
    for line in lines[first:last]:
        c = [x.strip() for x in CELL.split(line)[1:-1]]
        cells[c[0]] = c
    return first, last, cells


def main():
    args = sys.argv[1:]
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'lib')
    if args and args[0] in ('--update', '--check'):
        doc = args[1]
        lines = open(doc).read().split('\n')
        first, last, cells = doc_table(lines)
        want = rows(root)
        if args[0] == '--check':
            names = {r[0] for r in want}
            problems = [f'missing: {r[0]}' for r in want if r[0] not in cells]
            problems += [f'gone from the headers: {p}' for p in cells if p not in names]
            problems += [f'stale default or meaning: {r[0]}' for r in want
                         if r[0] in cells and cells[r[0]][1:3] != [r[1], r[2]]]
            for p in problems:
                print(f'{doc}: {p}')
            if problems:
                print('run: tools/options_table.py --update ' + doc + ' (then fill in how new defaults were measured)')
            return 1 if problems else 0
        body = []
        for p, default, meaning in want:
            # An unescaped '|' in the hand-written history splits it into several cells: keep them all.
            history = ' \\| '.join(c for c in cells[p][3:] if c) if p in cells else ''
            body.append(f'| {p} | {default} | {meaning} | {history} |')
        open(doc, 'w').write('\n'.join(lines[:first] + body + lines[last:]))
        return 0
    if args:
        root = args[0]
    print('| Parameter | Default | Meaning, unit (from the header) |')
    print('|---|---|---|')
    for p, default, meaning in rows(root):
        print(f'| {p} | {default} | {meaning} |')
    return 0


if __name__ == '__main__':
    sys.exit(main())
