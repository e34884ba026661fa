"""Reports of a reproduction: a self-contained HTML file with the figures, tables and verdicts."""

from .html import render_report, render_section, write_report

__all__ = ["render_report", "render_section", "write_report"]
