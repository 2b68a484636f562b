"""``reproduce`` leaves matplotlib's backend alone (a notebook's inline figures keep showing)."""

import matplotlib


def test_the_report_does_not_switch_the_backend(tmp_path):
    from clap_unified.reproduce import reproduce

    before = matplotlib.get_backend()
    matplotlib.use("svg")  # a backend the report would replace if it switched
    try:
        reproduce(tmp_path, only=["localization2d"], quick=True, progress=False,
                  log=lambda s: None)
        assert matplotlib.get_backend() == "svg"
    finally:
        matplotlib.use(before)
