import json

import numpy as np
import pytest

from clap_unified.maps.field import (
    FIELD_DIMENSIONS,
    LANDMARK_TYPES,
    field_landmarks,
    load_field,
)


@pytest.mark.parametrize("name", ["adult", "kid"])
def test_field_files_match_the_rule_dimensions(name):
    f = load_field(name)
    expected = field_landmarks(FIELD_DIMENSIONS[name])
    assert f.types.tolist() == [m["type"] for m in expected]
    np.testing.assert_allclose(f.positions, [[m["x"], m["y"]] for m in expected])
    # 180 degree symmetry: every landmark has a partner of the same type at -p
    for kind in LANDMARK_TYPES:
        p = f.of_type(kind)
        d = np.linalg.norm(p[:, None] + p[None], axis=-1)
        assert np.all(d.min(axis=1) < 1e-12)


def test_bad_field_files(tmp_path):
    with pytest.raises(ValueError, match="name"):
        load_field("giant")
    with pytest.raises(ValueError, match="no such field file"):
        load_field(path=tmp_path / "none.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    with pytest.raises(ValueError, match="not a valid field file"):
        load_field(path=bad)
    bad.write_text(json.dumps({"landmarks": [{"type": "Q", "x": 0, "y": 0}]}))
    with pytest.raises(ValueError, match="unknown landmark types"):
        load_field(path=bad)
