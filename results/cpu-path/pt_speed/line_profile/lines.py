"""perf samples of smlt's own code by source line: reads symoff.txt (count, symbol, offset, from
`perf script`) and nmC.txt (`nm -C` of the binary), maps each address through `addr2line -i` of
the binary given (built with line tables) and prints the shares by leaf file, by the
path_tracer.rs line each sample lies under, by leaf line, and the callers of the hottest lines
(sunblind.txt says how they were made). A measurement, not a tool.
    python3 lines.py BINARY
"""
import subprocess, collections, sys
nm = {}
for line in open("nmC.txt"):
    p = line.rstrip("\n").split(" ", 2)
    if len(p) == 3 and p[0] and p[1] in "tTwW": nm.setdefault(p[2], int(p[0], 16))
rows = []; miss = 0
for line in open("symoff.txt"):
    c, rest = line.strip().split(" ", 1)
    sym, off = rest.rsplit("\t", 1)
    if sym not in nm: miss += int(c); continue
    rows.append((int(c), nm[sym] + int(off, 16)))
out = subprocess.run(["addr2line", "-a", "-i", "-e", sys.argv[1]] + [hex(a) for _, a in rows], capture_output=True, text=True).stdout
chains = {}; cur = None
for l in out.splitlines():
    if l.startswith("0x"):
        cur = int(l, 16); chains[cur] = []
    else:
        chains[cur].append(l.replace("/work/main/", "").split(" (")[0])
total = sum(c for c, _ in rows)
print("samples", total, "unmapped", miss)
inner = collections.Counter(); byfile = collections.Counter(); scatter_line = collections.Counter()
for c, a in rows:
    ch = chains.get(a, ["?"])
    inner[ch[0]] += c
    byfile[ch[0].split(":")[0]] += c
    for x in ch:
        if "path_tracer.rs" in x:
            scatter_line[x] += c; break
    else:
        scatter_line["(not under path_tracer.rs)"] += c
print("== by leaf file"); [print(f"{100*v/total:5.1f}% {k}") for k, v in byfile.most_common(25)]
print("== by the path_tracer.rs line it is under"); [print(f"{100*v/total:5.1f}% {k}") for k, v in scatter_line.most_common(40)]
print("== leaf lines"); [print(f"{100*v/total:5.1f}% {k}") for k, v in inner.most_common(30)]
par = collections.Counter()
for c, a in rows:
    ch = chains.get(a, ["?"])
    if ch[0].split(":")[0].endswith(("vec3.rs", "arith.rs", "f32.rs")):
        par[ch[1] if len(ch) > 1 else "?"] += c
print("== parents of glam/arith leaves"); [print(f"{100*v/total:5.1f}% {k}") for k, v in par.most_common(30)]
bs = collections.Counter()
for c, a in rows:
    ch = chains.get(a, ["?"])
    for x in ch:
        if x.startswith("shared/src/bsdf.rs"):
            bs[x] += c; break
print("== first bsdf.rs frame"); [print(f"{100*v/total:5.1f}% {k}") for k, v in bs.most_common(25)]
ob = collections.Counter()
for c, a in rows:
    ch = chains.get(a, ["?"])
    for i, x in enumerate(ch):
        if x.startswith("shared/src/bsdf.rs:2") and x.split(":")[1] in ("269","270","271","272"):
            ob[" <- ".join(ch[i+1:i+4])] += c; break
print("== callers of orthonormal_basis"); [print(f"{100*v/total:5.1f}% {k}") for k, v in ob.most_common(10)]
