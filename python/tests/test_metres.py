"""The figures' lengths as the Rust side writes them (core's
`figure::metres`, whose test holds the same values): the progress bar's
last words and a figure's title read alike from Python and the CLI."""

from nvector._client import metres


def test_metres_matches_the_rust_formatting() -> None:
    assert metres(73.02259360692675) == "73.0 m"
    assert metres(612.4) == "612 m"
    assert metres(0.4123) == "0.412 m"
    assert metres(0.0) == "0 m"
    # Rust's `{:.2e}`: no zero padding, no plus sign in the exponent.
    assert metres(0.004) == "4.00e-3 m"
    assert metres(9_999_999.0) == "9999999 m"
    assert metres(1e308) == "1.00e308 m"
    assert metres(-1.7e308) == "-1.70e308 m"
    assert metres("inf") == "unbounded"
    assert metres(None) == "?"
