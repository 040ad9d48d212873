#!/usr/bin/env python3
"""Lists the C++ functions longer than a limit outside the tests.

A function's length runs from the line its signature starts on to its
closing brace, counted by matching braces in the source with comments,
string literals and preprocessor lines blanked out. Exits 1 when any
function is longer than the limit (the house rule is 150 lines outside
generated and test code), 0 otherwise.

    python3 scripts/long_functions.py 150 core energies solvers scales methods \
        experiments apps python bench
"""
import os
import re
import sys

def strip(src):
    out = []; i = 0; n = len(src)
    while i < n:
        c = src[i]
        if src.startswith('//', i):
            j = src.find('\n', i); j = n if j < 0 else j
            out.append(' ' * (j - i)); i = j
        elif src.startswith('/*', i):
            j = src.find('*/', i + 2); j = n if j < 0 else j + 2
            out.append(re.sub(r'[^\n]', ' ', src[i:j])); i = j
        elif src.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', src[i:])
            end = src.find(')' + m.group(1) + '"', i) + len(m.group(1)) + 2
            out.append(re.sub(r'[^\n]', ' ', src[i:end])); i = end
        elif c in '"\'':
            j = i + 1
            while j < n and src[j] != c:
                j += 2 if src[j] == '\\' else 1
            out.append(c + ' ' * (j - i - 1) + c); i = j + 1
        else:
            out.append(c); i += 1
    s = ''.join(out)
    # preprocessor lines
    return re.sub(r'(?m)^[ \t]*#.*(\\\n.*)*$', lambda m: re.sub(r'[^\n]', ' ', m.group(0)), s)

def scan(path, limit):
    s = strip(open(path, encoding='utf-8', errors='replace').read())
    res = []
    stack = []  # entries: ('scope'|'func'|'other', start_line, name)
    header_start = 0  # index just after last ; { }
    for i, c in enumerate(s):
        if c == '{':
            head = s[header_start:i]
            in_func = any(k == 'func' for k, _, _ in stack)
            kind = 'other'
            if not in_func:
                h = ' '.join(head.split())
                if re.search(r'\b(namespace|class|struct|union|enum)\b', h) and '(' not in h.split(':')[0]:
                    kind = 'scope'
                elif re.match(r'^extern\s', h):
                    kind = 'scope'
                elif '(' in h and not re.search(r'=\s*$', h) and not re.match(r'^(if|for|while|switch)\b', h):
                    kind = 'func'
            if kind == 'func':
                # first non-space char of the header
                off = len(head) - len(head.lstrip())
                start = s.count('\n', 0, header_start + off) + 1
                name = re.findall(r'([~\w:]+(?:operator\S*)?)\s*\(', ' '.join(head.split()))
                stack.append(('func', start, name[0] if name else '?'))
            else:
                stack.append((kind, 0, ''))
            header_start = i + 1
        elif c == '}':
            if stack:
                kind, start, name = stack.pop()
                if kind == 'func':
                    end = s.count('\n', 0, i) + 1
                    length = end - start + 1
                    if length > limit:
                        res.append((length, path, start, name))
            header_start = i + 1
        elif c == ';':
            header_start = i + 1
    return res

if __name__ == '__main__':
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    limit = int(sys.argv[1])
    out = []
    for root in sys.argv[2:]:
        for dp, dn, fn in os.walk(root):
            dn[:] = [d for d in dn if d not in ('tests', 'build', '.git')]
            for f in fn:
                if f.endswith(('.cc', '.h', '.cpp', '.hpp')):
                    out += scan(os.path.join(dp, f), limit)
    for length, path, start, name in sorted(out, reverse=True):
        print(f'{length:5d}  {path}:{start}  {name}')
    sys.exit(1 if out else 0)
