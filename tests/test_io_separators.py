"""A points file written with another separator than the comma: the message names it."""

import pytest

from clap_unified.io import read_points_csv


@pytest.mark.parametrize("content, name", [
    ("x;y\n1.0;2.0\n3.0;4.0\n", "semicolons (';')"),
    ("1.0;2.0\n3.0;4.0\n", "semicolons (';')"),
    ("1.0\t2.0\n3.0\t4.0\n", "tabs ('\\t')"),
    ("1.0 2.0\n3.0 4.0\n", "spaces"),
    ("1.0   2.0\n", "spaces"),
    ("1|2\n", "vertical bars ('|')"),
])
def test_other_separator_is_named(tmp_path, content, name):
    f = tmp_path / "points.csv"
    f.write_text(content)
    with pytest.raises(ValueError) as info:
        read_points_csv(f)
    msg = str(info.value)
    assert str(f) in msg and "expected 2 values, got 1" in msg
    assert f"separated by {name}" in msg and "comma-separated, as 'x,y'" in msg


def test_four_columns_example_names_four_values(tmp_path):
    f = tmp_path / "matches.csv"
    f.write_text("1;2;3;4\n")
    with pytest.raises(ValueError, match="as 'v1,v2,v3,v4'"):
        read_points_csv(f, columns=4)


@pytest.mark.parametrize("content", ["1,2,3\n", "1\n2\n"])
def test_no_hint_without_another_separator(tmp_path, content):
    # three comma-separated values, or one value per line: nothing to name
    f = tmp_path / "points.csv"
    f.write_text(content)
    with pytest.raises(ValueError) as info:
        read_points_csv(f)
    assert "expected 2 values" in str(info.value) and "separated by" not in str(info.value)


def test_comma_file_still_reads(tmp_path):
    f = tmp_path / "points.csv"
    f.write_text("x,y\n1,2\n3,4\n")
    assert read_points_csv(f).tolist() == [[1.0, 2.0], [3.0, 4.0]]
