# SPDX-License-Identifier: GPL-3.0-or-later
"""build/report/mutation.md and mutation.json from the outcomes of a run."""

import json
import os
from collections import Counter, defaultdict

DETECTED = ("killed", "timeout")
VERDICTS = ("killed", "timeout", "survived", "invalid", "same-object")


def score(rows):
    detected = sum(1 for r in rows if r["verdict"] in DETECTED)
    counted = detected + sum(1 for r in rows if r["verdict"] == "survived")
    return detected, counted, (100.0 * detected / counted if counted else 100.0)


def _table(rows, key, title):
    groups = defaultdict(list)
    for r in rows:
        groups[r[key]].append(r)
    out = [
        f"| {title} | " + " | ".join(VERDICTS) + " | score |",
        "|---|" + "---:|" * (len(VERDICTS) + 1),
    ]
    for name in sorted(groups):
        c = Counter(r["verdict"] for r in groups[name])
        d, n, s = score(groups[name])
        out.append(
            f"| {name} | " + " | ".join(str(c[v]) for v in VERDICTS) + f" | {d}/{n} = {s:.1f} % |"
        )
    return out


def _code(s):
    return "`" + s.replace("`", "'").replace("|", "\\|") + "`"


def write(prefix, meta, rows, equivalents, stale):
    """Writes prefix.md and prefix.json; returns the paths."""
    os.makedirs(os.path.dirname(prefix), exist_ok=True)
    detected, counted, pct = score(rows)
    meta = dict(meta, detected=detected, counted=counted, score=round(pct, 2))
    with open(prefix + ".json", "w") as f:
        json.dump(
            {"meta": meta, "mutants": rows, "equivalent": equivalents, "stale_equivalent": stale},
            f,
            indent=1,
        )
    survivors = [r for r in rows if r["verdict"] == "survived"]
    md = (
        [
            f"# Mutation testing of src/ ({meta['mode']})",
            "",
            f"Score: **{detected} / {counted} = {pct:.1f} %** killed (a timeout counts as "
            f"killed), over the valid mutants not listed as equivalent.",
            "",
            f"Sources: commit {meta['commit']}{' + local changes' if meta['dirty'] else ''}; "
            f"run {meta['started']} UTC, {meta['seconds']:.0f} s for {meta.get('ran', len(rows))} "
            f"mutants of {meta.get('generated', len(rows))} "
            f"({meta['mean_seconds']:.1f} s each on average; build {meta['mean_build']:.1f} s); "
            f"tests: labels {', '.join(meta['labels'])}, {meta['tests']} tests, "
            f"jobs {meta['jobs']}.",
            "",
            *(
                [f"Left out, failing before any mutation: {', '.join(meta['broken_tests'])}.", ""]
                if meta.get("broken_tests")
                else []
            ),
            "Verdicts: killed (a test failed), timeout (a test hung: killed), survived (every "
            "test passed), invalid (does not compile: not counted), same-object (the compiler "
            "made the same object code: equivalent, not counted).",
            "",
            "## Per file",
            "",
        ]
        + _table(rows, "file", "file")
        + ["", "## Per operator", ""]
        + _table(rows, "op", "operator")
        + ["", f"## Survivors ({len(survivors)})", ""]
    )
    for r in sorted(survivors, key=lambda r: (r["file"], r["line"], r["op"])):
        md.append(f"- {r['file']}:{r['line']} **{r['op']}** `{r['id']}`  ")
        md.append(f"  {_code(r['original'])}  ")
        md.append(f"  -> {_code(r['mutated'])}")
    md += ["", f"## Equivalent mutants ({len(equivalents)}, tests/mutation/equivalent.txt)", ""]
    for e in equivalents:
        md.append(f"- {e['file']}:{e['line']} **{e['op']}** `{e['id']}`: {e['reason']}  ")
        md.append(f"  {_code(e['original'])} -> {_code(e['mutated'])}")
    same = [r for r in rows if r["verdict"] == "same-object"]
    if same:
        md += ["", f"## Same object code ({len(same)})", ""]
        md += [f"- {r['file']}:{r['line']} `{r['id']}`: {_code(r['mutated'])}" for r in same]
    if stale:
        md += ["", "## Stale entries of equivalent.txt (no such mutant today)", ""]
        md += [f"- `{s}`" for s in stale]
    with open(prefix + ".md", "w") as f:
        f.write("\n".join(md) + "\n")
    return prefix + ".md", prefix + ".json"
