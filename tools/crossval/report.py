# SPDX-License-Identifier: GPL-3.0-or-later
"""The report: one Section per check (Markdown text, tables, figures, summary values and
failures), written as one Markdown file ending with the summary block of `name: value` lines."""

import datetime
import os


def fmt(value):
    if isinstance(value, float):
        return "%.3g" % value
    return str(value)


class Section:
    def __init__(self, key, title):
        self.key, self.title = key, title
        self.lines, self.summary, self.failures = [], {}, []

    def text(self, paragraph):
        self.lines += [paragraph.strip(), ""]

    def table(self, header, rows):
        def line(cells):  # a | inside a cell (|xi|) must not end it
            return "| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |"

        self.lines.append(line(header))
        self.lines.append("|" + "---|" * len(header))
        self.lines += [line([fmt(v) for v in row]) for row in rows]
        self.lines.append("")

    def figure(self, filename, caption):
        self.lines += ["![%s](%s)" % (caption, filename), "", "*%s*" % caption, ""]

    def value(self, name, value, form="%.3g"):
        """A line of the summary block (numbers written with form)."""
        self.summary[name] = form % value if isinstance(value, float) else str(value)

    def expect(self, ok, what):
        """Records a failure of this check when not ok; returns ok."""
        if not ok:
            self.failures.append(what)
        return bool(ok)

    def verdict(self):
        return "pass" if not self.failures else "FAIL (%d)" % len(self.failures)


def write(path, sections, profile, seconds):
    lines = [
        "# stabdae cross-validation (%s run)" % profile.name,
        "",
        "Written by `tools/crossval/crossval%s` on %s in %.0f s. Each check states its "
        "tolerance; a failed check is listed under Failures and makes tools/crossval/crossval "
        "exit 1."
        % (
            " --full" if profile.name == "full" else "",
            datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
            seconds,
        ),
        "",
    ]
    lines += ["| check | verdict |", "|---|---|"]
    lines += ["| %s. %s | %s |" % (s.key, s.title, s.verdict()) for s in sections]
    lines.append("")
    for s in sections:
        lines += ["## %s. %s" % (s.key, s.title), ""] + s.lines
    failures = [(s.key, f) for s in sections for f in s.failures]
    lines += ["## Failures", ""]
    lines += ["- %s: %s" % kf for kf in failures] or ["None."]
    lines += ["", "## Summary", "", "```"]
    for s in sections:
        lines += ["%s: %s" % (k, fmt(v)) for k, v in s.summary.items()]
    lines += [
        "checks_failed: %d" % len(failures),
        "status: %s" % ("pass" if not failures else "FAIL"),
        "```",
        "",
    ]
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write("\n".join(lines))
    return failures
