"""A self-contained HTML page for one or more verification reports (inline SVG, no scripts, opens offline)."""

from __future__ import annotations

import html
import math
from collections.abc import Sequence

from .report import LinkInfo, VerifyReport

__all__ = ["reports_to_html"]

_CSS = """
body{font-family:system-ui,sans-serif;margin:2em;color:#222}
table{border-collapse:collapse;font-size:13px;margin:1em 0}
td,th{border:1px solid #ccc;padding:3px 8px;text-align:left}
th{background:#f0f0f0} .pass{color:#070} .fail{color:#b00;font-weight:bold}
.summary{font-size:15px;margin:.5em 0} h2{margin-top:2em} .note{color:#666;font-size:12px}
"""


def _error_chart(report: VerifyReport) -> str:
    """Per quantity: a bar to the largest relative error, a dot per sample (the distribution), the tolerance in red."""
    rows = [r for r in report.results if math.isfinite(r.max_rel)]
    if not rows:
        return ""
    lo, hi = -17.0, 0.0
    width, bar_h, label_w = 760, 14, 430
    h = bar_h * len(rows) + 40
    plot_w = width - label_w - 20

    def x(val: float) -> float:
        lv = math.log10(val) if val > 0 else lo
        return label_w + (min(max(lv, lo), hi) - lo) / (hi - lo) * plot_w

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{h}" font-size="10">']
    for k in range(int(lo), int(hi) + 1, 2):
        xx = label_w + (k - lo) / (hi - lo) * plot_w
        parts.append(f'<line x1="{xx:.1f}" y1="0" x2="{xx:.1f}" y2="{h - 25}" stroke="#eee"/>')
        parts.append(f'<text x="{xx:.1f}" y="{h - 10}" text-anchor="middle">1e{k}</text>')
    for i, r in enumerate(rows):
        y = i * bar_h + 2
        color = "#4a8" if r.passed else "#d33"
        parts.append(f'<text x="{label_w - 5}" y="{y + 10}" text-anchor="end">{html.escape(r.quantity[:70])}</text>')
        parts.append(f'<rect x="{label_w}" y="{y}" width="{max(x(r.max_rel) - label_w, 1):.1f}" '
                     f'height="{bar_h - 3}" fill="{color}"/>')
        for e in r.sample_errors:
            parts.append(f'<circle cx="{x(e):.1f}" cy="{y + (bar_h - 3) / 2:.1f}" r="2" fill="#124" '
                         'fill-opacity="0.5"/>')
        tx = x(r.tol)
        parts.append(f'<line x1="{tx:.1f}" y1="{y}" x2="{tx:.1f}" y2="{y + bar_h - 3}" stroke="#b00"/>')
    parts.append("</svg>")
    return "".join(parts)


def _ellipse(link: LinkInfo) -> str:
    """A glyph of the link's equivalent uniform ellipsoid (its two largest semi-axes), or a red cross if none exists."""
    axes = link.get("ellipsoid_semi_axes")
    if not axes:
        return ('<svg xmlns="http://www.w3.org/2000/svg" width="40" height="24"><path d="M12 4 L28 20 M28 4 L12 20" '
                'stroke="#d33" stroke-width="2"/></svg>')
    a, b = sorted(axes)[-1], sorted(axes)[-2]
    scale = 18 / max(a, 1e-12)
    return (f'<svg xmlns="http://www.w3.org/2000/svg" width="40" height="24"><ellipse cx="20" cy="12" '
            f'rx="{a * scale:.1f}" ry="{max(b * scale, 0.5):.1f}" fill="#9cd" stroke="#246"/></svg>'
            f' {a:.3g} × {b:.3g} m')


def _inertia_chart(report: VerifyReport) -> str:
    d = report.diagnostics
    if not d:
        return ""
    n_bad = len(d.get("invalid_inertias", []))
    n_all = int(report.meta.get("nbodies", 0))
    n_ok = max(n_all - n_bad, 0)
    total = max(n_all, 1)
    w = 400
    ok_w = w * n_ok / total
    svg = (f'<svg xmlns="http://www.w3.org/2000/svg" width="{w + 10}" height="40" font-size="11">'
           f'<rect x="0" y="0" width="{ok_w:.1f}" height="20" fill="#4a8"/>'
           f'<rect x="{ok_w:.1f}" y="0" width="{w - ok_w:.1f}" height="20" fill="#d33"/>'
           f'<text x="0" y="34">{n_ok} physical</text>'
           f'<text x="{w}" y="34" text-anchor="end">{n_bad} not physical</text></svg>')
    rows = "".join(
        f"<tr><td>{html.escape(link['body'])}</td><td>{link['mass']:.4g}</td>"
        f"<td>{', '.join(f'{x:.3g}' for x in link['principal_moments'])}</td><td>{_ellipse(link)}</td>"
        f"<td class='{'pass' if link['valid'] else 'fail'}'>{'physical' if link['valid'] else 'NOT physical'}</td>"
        f"<td class='note'>{html.escape(link['reason'].split(': ', 1)[-1])}</td></tr>"
        for link in d.get("links", [])
    )
    table = ("<table><tr><th>body</th><th>mass (kg)</th><th>principal moments (kg m²)</th>"
             "<th>equivalent ellipsoid</th><th>validity</th><th>reason</th></tr>" + rows + "</table>") if rows else ""
    sing = "".join(f"<li>{html.escape(s)}</li>" for s in d.get("singular_subtrees", []))
    cond = d.get("mass_matrix_condition")
    extra = f"<p>mass-matrix condition number (worst of 4 random states): {cond:.3g}</p>" \
        if isinstance(cond, float) else ""
    return svg + table + (f"<p>singular subtrees:</p><ul>{sing}</ul>" if sing else "") + extra


def _refused(report: VerifyReport) -> str:
    """"refused by Drake" when the oracle asked for could not take the model (nothing compared), else ``""``."""
    skipped = report.meta.get("oracles_skipped", {})
    oracle = str(report.meta.get("oracle", ""))
    return f"refused by {oracle.capitalize()}" if oracle in skipped else ""


def _one(report: VerifyReport) -> str:
    status = '<span class="pass">all checks pass</span>' if report.passed else \
        f'<span class="fail">{len(report.failures)} checks fail</span>'
    if _refused(report):  # not a failure: the oracle's reason is listed below
        status = f"{_refused(report)}: not compared"
    rows = []
    for r in report.results:
        cls = "pass" if r.passed else "fail"
        rows.append(
            f"<tr><td>{html.escape(r.group)}</td><td>{html.escape(r.quantity)}</td><td>{r.max_abs:.2e}</td>"
            f"<td>{r.max_rel:.2e}</td><td>{r.worst_sample}</td><td>{r.tol:.0e}</td>"
            f'<td class="{cls}">{"pass" if r.passed else "FAIL"}</td><td class="note">{html.escape(r.note)}'
            + (f"<br>{html.escape(r.criterion)}" if r.criterion else "") + "</td></tr>"
        )
    meta = "".join(f"<tr><th>{html.escape(str(k))}</th><td>{html.escape(str(v))}</td></tr>"
                   for k, v in report.meta.items() if k not in ("load_warnings", "drake_warnings", "oracle_notes"))
    warns = "".join(f"<li>{html.escape(w)}</li>" for w in report.meta.get("load_warnings", []))
    notes = "".join(f"<li>{html.escape(n)}</li>" for n in report.meta.get("oracle_notes", []))
    notes += "".join(f"<li>{html.escape(k)} left out: {html.escape(v)}</li>"
                     for k, v in report.meta.get("oracles_skipped", {}).items())
    return (
        f"<h2>{html.escape(report.title)}</h2><p class='summary'>{status}</p>"
        f"<h3>Relative error per quantity (log scale; bar = worst state, dots = every state, red line = tolerance)</h3>{_error_chart(report)}"
        "<h3>Results</h3><table><tr><th>group</th><th>quantity</th><th>max abs</th><th>max rel</th>"
        f"<th>worst state</th><th>tol</th><th>result</th><th>likely cause; how judged</th></tr>{''.join(rows)}</table>"
        f"<h3>Link inertias</h3>{_inertia_chart(report)}"
        + (f"<h3>Warnings while loading</h3><ul>{warns}</ul>" if warns else "")
        + (f"<h3>What the oracles ignore or leave out</h3><ul>{notes}</ul>" if notes else "")
        + f"<h3>Run</h3><table>{meta}</table>"
    )


def reports_to_html(reports: Sequence[VerifyReport], title: str = "featherdyn verify") -> str:
    """One HTML document with a summary table and a section per report."""
    summary = "".join(
        f"<tr><td>{html.escape(r.meta.get('robot', r.title))}</td>"
        f"<td>{'floating' if r.meta.get('floating_base') else 'fixed'}</td>"
        f"<td>{html.escape(str(r.meta.get('oracle', '')))}</td>"
        f"<td>{len(r.results)}</td><td class='{'pass' if r.passed else 'fail'}'>"
        f"{_refused(r) or len(r.failures)}</td></tr>"
        for r in reports
    )
    head = f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>" \
           f"<style>{_CSS}</style></head><body><h1>{html.escape(title)}</h1>"
    table = f"<table><tr><th>robot</th><th>base</th><th>oracle</th><th>checks</th><th>failed</th></tr>{summary}</table>" \
        if len(reports) > 1 else ""
    return head + table + "".join(_one(r) for r in reports) + "</body></html>\n"
