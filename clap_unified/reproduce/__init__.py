"""Regenerating the paper: experiments, claims with verdicts, figures, one command.

``clap-unified reproduce [--quick] [--out DIR] [--jobs N] [--scheduler ADDRESS]``
runs every registered experiment (:data:`EXPERIMENTS`), judges every claim of
the paper (:data:`CLAIMS`) and writes ``claims.json``, ``claims.md``, the CSV
tables and the figures into ``DIR`` (:func:`reproduce`).
"""

from . import exp_homography, exp_localization, exp_multimodel  # noqa: F401  (the experiments)
from .claims import (
    CLAIM_TITLES,
    CLAIMS,
    VERDICTS,
    alternatives_count,
    alternatives_text,
    chapter_claims,
    claim_block,
    claim_title,
    describe_variant,
    evaluate_claims,
    verdict_lines,
)
from .registry import EXPERIMENTS, seed_for
from .runner import MissingDataError, Reproduction, claims_markdown, reproduce, verdicts_markdown

__all__ = ["CLAIMS", "CLAIM_TITLES", "EXPERIMENTS", "VERDICTS", "MissingDataError",
           "Reproduction", "alternatives_count", "alternatives_text", "chapter_claims",
           "claim_block", "claim_title", "claims_markdown", "describe_variant", "evaluate_claims",
           "reproduce", "seed_for", "verdict_lines", "verdicts_markdown"]
