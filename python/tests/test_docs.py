"""The examples in the docstrings run and print what they show."""

import doctest

import stabound


def test_docstring_examples():
    failures, tried = doctest.testmod(stabound, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried > 10
    assert failures == 0
