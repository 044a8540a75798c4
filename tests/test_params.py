import re

import pytest
import yaml

from navlab.core.params import ParamsError, load_params


def _write(tmp_path, mutate):
    with open("params.yaml") as fh:
        raw = yaml.safe_load(fh)
    mutate(raw)
    path = tmp_path / "params.yaml"
    path.write_text(yaml.safe_dump(raw))
    return path


@pytest.mark.parametrize("profile", ["smoke", "default", "gpu", "paper"])
def test_every_profile_validates(profile):
    assert load_params(profile).profile == profile


def test_profile_leaf_resolves():
    assert load_params("smoke").quickstart.resolution_m == 2.0
    assert load_params("default").quickstart.resolution_m == 1.0


def test_unknown_key_names_the_key(tmp_path):
    path = _write(tmp_path, lambda r: r["quickstart"].update(bogus=1))
    with pytest.raises(ParamsError, match=r"^quickstart\.bogus: unknown key"):
        load_params("smoke", path)


def test_wrong_type_names_key_and_value(tmp_path):
    path = _write(tmp_path, lambda r: r["quickstart"].update(queries="many"))
    with pytest.raises(ParamsError) as err:
        load_params("smoke", path)
    msg = str(err.value)
    assert "quickstart.queries" in msg and "'many'" in msg and "integer" in msg
    assert "\n" not in msg


def test_out_of_range_says_what_is_allowed(tmp_path):
    path = _write(tmp_path, lambda r: r["quickstart"].update(resolution_m={"default": 1.0, "smoke": 0.0}))
    with pytest.raises(ParamsError, match=re.escape("quickstart.resolution_m = 0.0: out of range")):
        load_params("smoke", path)
    assert load_params("default", path).quickstart.resolution_m == 1.0


def test_missing_key_and_bad_choice(tmp_path):
    path = _write(tmp_path, lambda r: r["quickstart"].pop("city"))
    with pytest.raises(ParamsError, match=r"quickstart\.city: missing"):
        load_params("smoke", path)
    path = _write(tmp_path, lambda r: r["quickstart"].update(city="paris"))
    with pytest.raises(ParamsError, match=r"quickstart\.city = 'paris': allowed values"):
        load_params("smoke", path)


def test_unknown_profile():
    with pytest.raises(ParamsError, match="allowed profiles"):
        load_params("huge")


def test_reversed_ranges_name_the_keys(tmp_path):
    path = _write(tmp_path, lambda r: r["data"]["demos"].update(min_distance_m=300.0))
    with pytest.raises(ParamsError, match=r"^data\.demos\.min_distance_m = 300.0 exceeds max_distance_m = 200.0"):
        load_params("smoke", path)
    path = _write(tmp_path, lambda r: r["data"]["maps"]["procedural"].update(block_size_m=[140.0, 60.0]))
    with pytest.raises(ParamsError, match=re.escape("data.maps.procedural.block_size_m = [140.0, 60.0]: give [min")):
        load_params("smoke", path)


def test_profile_mapping_without_default_names_the_key(tmp_path):
    path = _write(tmp_path, lambda r: r["quickstart"].update(queries={"smoke": 3, "paper": 100}))
    with pytest.raises(ParamsError, match=r"^quickstart\.queries = .*needs a 'default' value"):
        load_params("smoke", path)
