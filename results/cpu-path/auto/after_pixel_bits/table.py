"""The docs' auto table from each view's tables.md and auto.csv: python3 table.py FOLDER."""
import csv
import re
import sys

HERE = sys.argv[1]
VIEWS = [('sibenik', 'Sibenik'), ('sponza', 'Sponza v1'), ('banner2', 'banner v2'), ('sunblind', '`sunblind`'),
         ('slit', '`slit`'), ('atrium1', 'atrium v1'), ('atrium2', 'atrium v2')]
METHODS = ['auto', 'pt', 'naive', 'path-naive', 's3']
PEERS = [('mitsuba-path', 'Mitsuba 3 `path`', 'Mitsuba 3'), ('cycles-path', 'Cycles, Blender 5.0.1', 'Cycles')]


def number(x):
    if x == '∞':
        return x
    x = float(x)
    return f"{x:.3g}" if x < 1000 else f"{x:.0f}"


def efficiencies(view):
    table = open(f"{HERE}/{view}/tables.md").read().split('### Efficiency')[1].split('###')[0]
    out = {}
    for line in table.splitlines():
        m = re.match(r'\| (\S+) \| \**([0-9.]+) \(([0-9.]+)–([0-9.∞]+)\)', line)
        if m:
            out[m.group(1)] = (float(m.group(2)), m.group(3), m.group(4))
    return out


def cell(e):
    return f"{number(e[0])} ({number(e[1])}–{number(e[2])})"


eff = {v: efficiencies(v) for v, _ in VIEWS}
best = {v: max(e[0] for m, e in eff[v].items() if m in METHODS[1:]) for v, _ in VIEWS}
print('| | ' + ' | '.join(n for _, n in VIEWS) + ' |')
print('|---' * (len(VIEWS) + 1) + '|')
chose, pilot = [], []
for v, _ in VIEWS:
    rows = {r['repeat']: r for r in csv.DictReader(open(f"{HERE}/{v}/auto.csv"))}
    c = [rows[k]['chosen'] for k in sorted(rows)]
    chose.append(f"{c[0]} ×3" if len(set(c)) == 1 else ', '.join(c))
    s = [float(r['pilot_seconds']) for r in rows.values()]
    pilot.append(f"{min(s):.2f}–{max(s):.2f}")
print('| auto chose (runs 1, 2, 3) | ' + ' | '.join(chose) + ' |')
print("| auto's pilot, s of the 8 | " + ' | '.join(pilot) + ' |')
for m in METHODS:
    cells = []
    for v, _ in VIEWS:
        c = cell(eff[v][m])
        cells.append(f"**{c}**" if m != 'auto' and eff[v][m][0] == best[v] else c)
    print(f"| `{m}` | " + ' | '.join(cells) + ' |')
print('| auto / best single | ' + ' | '.join(f"{eff[v]['auto'][0] / best[v]:.2f}" for v, _ in VIEWS) + ' |')
for key, row, short in PEERS:
    print(f"| {row} | " + ' | '.join(cell(eff[v][key]) if key in eff[v] else '—' for v, _ in VIEWS) + ' |')
    print(f"| auto / {short} | " + ' | '.join(
        f"{eff[v]['auto'][0] / eff[v][key][0]:.2f}" if key in eff[v] else '—' for v, _ in VIEWS) + ' |')
