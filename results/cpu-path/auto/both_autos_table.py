# Reads the view folders of a both_autos.sh run (bench_tables.md, old_bench_tables.md, auto.csv,
# old_auto.csv; showcase/lamp and showcase/sky where there are) and prints the docs table, the
# previous auto's row named by LABEL:
#   python3 both_autos_table.py FOLDER LABEL > FOLDER/table.md
import csv, os, re, sys, collections
here, label = sys.argv[1], sys.argv[2]
views = ["sibenik", "sponza", "banner2", "sunblind", "slit", "atrium1", "atrium2", "showcase/lamp", "showcase/sky"]
def eff(path):
    out = {}
    lines = open(path).read().split("### ")
    sec = [l for l in lines if l.startswith("Efficiency")][0]
    for row in sec.splitlines():
        # (a † marks a method the bench found missing light: the path tracers on the lamps' caustic)
        m = re.match(r"\| ([a-z0-9-]+) \| \**([0-9.]+) \(([^)]*)\)\**( †)? \|", row)
        if m:
            out[m.group(1)] = (float(m.group(2)), m.group(3))
    return out
def chose(path):
    c = collections.OrderedDict()
    for r in csv.DictReader(open(path)):
        c[r["repeat"]] = r["chosen"]
    return ", ".join(c.values())
rows = collections.defaultdict(list)
for v in views:
    d = os.path.join(here, v)
    if not os.path.isdir(d):
        continue
    new, old = eff(os.path.join(d, "bench_tables.md")), eff(os.path.join(d, "old_bench_tables.md"))
    singles = {k: x for k, x in new.items() if k != "auto"}
    best = max(singles, key=lambda k: singles[k][0])
    f = lambda x: f"{x[0]:.3g} ({x[1]})"
    rows["view"].append(v)
    rows["auto chose (runs 1, 2, 3)"].append(chose(os.path.join(d, "auto.csv")))
    rows["previous auto chose"].append(chose(os.path.join(d, "old_auto.csv")))
    rows["`auto`"].append(f(new["auto"]))
    rows[f"previous `auto` ({label})"].append(f(old["auto"]))
    for k in ["pt", "naive", "path-naive", "s3"]:
        rows[f"`{k}`"].append(("**" + f(new[k]) + "**") if k == best else f(new[k]))
    rows["auto / best single"].append(f"{new['auto'][0] / singles[best][0]:.2f}")
    rows["previous auto / best single"].append(f"{old['auto'][0] / singles[best][0]:.2f}")
keys = list(rows)
print("| " + " | ".join(["", *rows["view"]]) + " |")
print("|" + "---|" * (len(rows["view"]) + 1))
for k in keys[1:]:
    print("| " + " | ".join([k, *rows[k]]) + " |")
