"""Experiments built from many runs."""

from multibots.experiments.paper import PaperRow, format_paper_table, paper_scenarios, run_paper, write_paper_csv

__all__ = ["PaperRow", "format_paper_table", "paper_scenarios", "run_paper", "write_paper_csv"]
