#!/usr/bin/env python3
"""Prints a markdown table of every field of every `struct *Options` in lib/mesohex/**/*.h: parameter, default, and the
header's comment on it (meaning and unit). docs/tuning.md's parameter table starts from its output; the measurement
history column there is written by hand.

  tools/options_table.py [lib-dir]
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


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '..', 'lib')
    print('| Parameter | Default | Meaning, unit (from the header) |')
    print('|---|---|---|')
    for d, _, names in sorted(os.walk(root)):
        for n in sorted(names):
            if not n.endswith('.h'):
                continue
            for struct, field, default, comment in fields(open(os.path.join(d, n)).read()):
                text = ' '.join(comment).replace('|', '\\|')
                print(f'| `{struct}::{field}` | `{default}` | {text} |')


if __name__ == '__main__':
    main()
