import json, sys
d = json.load(open(sys.argv[1]))
med, cv = {}, {}
for b in d['benchmarks']:
    v = b.get('per_pt', b.get('per_knot'))
    if b.get('aggregate_name') == 'median': med[b['run_name']] = v * 1e9
    if b.get('aggregate_name') == 'cv': cv[b['run_name']] = v * 100
ROWS = [
    ("curve_eval_random", "cifs", "sisl_s1542_fresh"),
    ("curve_eval_random", "cifs", "sisl_s1542"),
    ("curve_eval_random", "cifs", "sisl"),
    ("curve_eval_random", "cifs", "sisl_s1221"),
    ("curve_eval_random", "cifs_deboor", "sisl"),
    ("curve_eval_random", "cifs_deboor", "sisl_s1221"),
    ("curve_eval_random", "cifs_basis", "sisl"),
    ("curve_eval_sorted", "cifs", "sisl_s1542_fresh"),
    ("curve_eval_sorted", "cifs", "sisl_s1542"),
    ("curve_eval_sorted", "cifs", "sisl"),
    ("curve_eval_sorted", "cifs", "sisl_s1221"),
    ("curve_eval_sorted", "cifs_deboor", "sisl"),
    ("curve_eval_sorted", "cifs_deboor", "sisl_s1221"),
    ("curve_eval_sorted", "cifs_basis", "sisl"),
    ("rcurve_eval_random", "cifs", "sisl"),
    ("rcurve_eval_random", "cifs", "sisl_s1221"),
    ("rcurve_eval_random", "cifs_deboor", "sisl"),
    ("rcurve_eval_random", "cifs_basis", "sisl"),
    ("rcurve_eval_sorted", "cifs", "sisl"),
    ("rcurve_eval_sorted", "cifs", "sisl_s1221"),
    ("rcurve_eval_sorted", "cifs_deboor", "sisl"),
    ("rcurve_eval_sorted", "cifs_deboor", "sisl_s1221"),
    ("rcurve_eval_sorted", "cifs_basis", "sisl"),
    ("surface_grid", "cifs", "sisl"),
    ("surface_grid", "cifs", "sisl_s1424"),
    ("surface_grid", "cifs_point", "sisl_s1424"),
    ("rsurface_grid", "cifs", "sisl"),
    ("rsurface_grid", "cifs", "sisl_s1424"),
    ("rsurface_grid", "cifs_point", "sisl_s1424"),
    ("curve_refine_1000", "cifs", "sisl"),
    ("curve_refine_1000", "cifs_midpoints", "sisl"),
    ("curve_refine_100000", "cifs", "sisl"),
    ("curve_refine_100000", "cifs_midpoints", "sisl"),
    ("curve_refine_dense_10000", "cifs", "sisl"),
]
SISL = {"sisl": "s1227 + leftknot", "sisl_s1221": "s1221 + leftknot", "sisl_s1542": "s1542 (stale hints)",
        "sisl_s1542_fresh": "s1542", "sisl_s1424": "s1424 per point"}
CIFS = {"cifs": "evaluate(c, us)", "cifs_deboor": "evaluate(c, u)", "cifs_basis": "evaluate_basis",
        "cifs_point": "evaluate(s, u, v)", "cifs_midpoints": "refine_midpoints"}
print("| case | cifs | ns | SISL | ns | SISL/cifs |")
print("|---|---|--:|---|--:|--:|")
for g, c, s in ROWS:
    cn = CIFS.get(c, c); sn = SISL.get(s, s)
    if "surface" in g:
        cn = "evaluate_grid" if c == "cifs" else cn
        sn = "s1506 grid" if s == "sisl" else sn
    if "refine" in g:
        cn = "refine(c, knots)" if c == "cifs" else cn
        sn = "s1018"
    a = med.get(f"BM_{g}/{c}"); b = med.get(f"BM_{g}/{s}")
    print(f"| {g} | {cn} | {a:.1f} | {sn} | {b:.1f} | {b/a:.2f} |")
cvs = sorted(cv.values())
print("median cv %.1f%%, worst %.1f%% (%s)" % (cvs[len(cvs)//2], cvs[-1], max(cv, key=cv.get)))
print("cifs_fresh", med.get("BM_curve_eval_random/cifs_fresh"), med.get("BM_curve_eval_sorted/cifs_fresh"))
