#!/usr/bin/env python3
"""Lengths of the functions defined in C++ sources (lines from the line of the signature's start to the closing brace,
lambdas counted in their enclosing function).

  tools/function_lengths.py [--max N] [--allow FILE] [--top K] PATH...

Lists the K longest functions (default 20). With --max, exits 1 when a function in a file not named in the allow-list
(one path relative to the repository per line, '#' comments) is longer than N lines. The parser is lexical: comments,
string and character literals are blanked, then every '{' at namespace or class scope whose header (the text since the
previous ';', '{' or '}') has a '(' and is not a namespace / class / struct / union / enum opens a function body.
"""
import argparse
import os
import re
import sys

SCOPE_RE = re.compile(r'\b(namespace|struct|class|union|enum)\b')


def blank(text):
    """Comments, string and char literals replaced by spaces (newlines kept, so line numbers stay)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith('//', i):
            j = text.find('\n', i)
            j = n if j < 0 else j
            out.append(' ' * (j - i)); i = j
        elif text.startswith('/*', i):
            j = text.find('*/', i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', text[i:j])); i = j
        elif c == 'R' and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if m:
                end = text.find(')' + m.group(1) + '"', i)
                end = n if end < 0 else end + len(m.group(1)) + 2
                out.append(re.sub(r'[^\n]', ' ', text[i:end])); i = end
            else:
                out.append(c); i += 1
        elif c in '"\'':
            if c == "'" and i > 0 and text[i - 1].isalnum() and text[i + 1:i + 2].isdigit():
                out.append(' '); i += 1  # digit separator 1'000
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            out.append(' ' * (min(j + 1, n) - i)); i = min(j + 1, n)
        else:
            out.append(c); i += 1
    return ''.join(out)


def functions(path):
    text = blank(open(path, encoding='utf-8', errors='replace').read())
    stack = []  # per open brace: 'scope' (namespace/class/...), 'func' or 'other'
    header_start, result, func_open = 0, [], None
    for i, c in enumerate(text):
        if c == '{':
            transparent = all(k == 'scope' for k in stack)
            header = text[header_start:i]
            if transparent and not SCOPE_RE.search(header.split('(')[0]) and '(' in header \
                    and not header.rstrip().endswith('='):
                kind = 'func'
                first = header_start + (len(header) - len(header.lstrip()))
                func_open = (text.count('\n', 0, first) + 1, re.sub(r'\s+', ' ', header.strip())[:100])
            elif transparent and SCOPE_RE.search(header) and '(' not in header.split('{')[0].split('=')[0]:
                kind = 'scope'
            else:
                kind = 'other'
            stack.append(kind)
            header_start = i + 1
        elif c == '}':
            if stack:
                kind = stack.pop()
                if kind == 'func' and all(k == 'scope' for k in stack):
                    end = text.count('\n', 0, i) + 1
                    result.append((end - func_open[0] + 1, func_open[0], func_open[1]))
            header_start = i + 1
        elif c == ';':
            header_start = i + 1
    return result


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('paths', nargs='+')
    ap.add_argument('--max', type=int)
    ap.add_argument('--allow')
    ap.add_argument('--top', type=int, default=20)
    ap.add_argument('--root', default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    a = ap.parse_args()
    allowed = set()
    if a.allow:
        for line in open(a.allow):
            line = line.split('#')[0].strip()
            if line:
                allowed.add(line)
    files = []
    for p in a.paths:
        if os.path.isdir(p):
            for d, _, names in os.walk(p):
                files += [os.path.join(d, f) for f in names if f.endswith(('.cpp', '.h', '.hpp', '.cc'))]
        else:
            files.append(p)
    rows = []
    for f in sorted(files):
        rel = os.path.relpath(os.path.abspath(f), a.root)
        rows += [(n, rel, line, sig) for n, line, sig in functions(f)]
    rows.sort(key=lambda r: (-r[0], r[1], r[2]))
    for n, rel, line, sig in rows[:a.top]:
        print(f'{n:5d}  {rel}:{line}  {sig}')
    if a.max is not None:
        over = [r for r in rows if r[0] > a.max and r[1] not in allowed]
        for n, rel, line, sig in over:
            print(f'error: {rel}:{line}: function of {n} lines (limit {a.max}): {sig}', file=sys.stderr)
        allowed_over = sorted({r[1] for r in rows if r[0] > a.max and r[1] in allowed})
        if allowed_over:
            print(f'allow-listed files still over {a.max}: ' + ', '.join(allowed_over))
        return 1 if over else 0
    return 0


if __name__ == '__main__':
    sys.exit(main())
