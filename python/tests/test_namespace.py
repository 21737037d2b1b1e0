"""The package's namespace is its API."""

import hopsim


def test_dir_lists_the_api_and_nothing_else():
    public = sorted(name for name in dir(hopsim) if not name.startswith("_"))
    assert public == sorted(hopsim.__all__)
    for name in hopsim.__all__:
        assert getattr(hopsim, name) is not None
