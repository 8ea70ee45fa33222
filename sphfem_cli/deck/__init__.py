"""Deck input: YAML with positions (``loader``), pydantic schema (``schema``), one-line errors.

Public API: :func:`load_deck` reads, parses and validates a deck file and returns the
``schema.Deck``; every problem is raised as a :class:`DeckError` whose ``str()`` is one line,
``file:line:col: path.in.deck: message``.
"""
from .errors import DeckError, DeckErrors, did_you_mean
from .validate import load_deck, validate_model

__all__ = ["DeckError", "DeckErrors", "did_you_mean", "load_deck", "validate_model"]
