"""User attributes: Habitat's exact get_as_string formats, types, sub-configurations."""

import numpy as np
import pytest

from engine import mn
from engine.templates.user_config import Configuration, ConfigValType


def test_get_as_string_formats_match_habitat():
    config = Configuration()
    config.set("obj_val_0", "This is a sphere object named " + "sphere")
    config.set("obj_val_1", 17)
    config.set("obj_val_2", False)
    config.set("obj_val_3", 19.7)
    config.set("obj_val_4", [2.50, 0.0, 0.2])
    config.set("obj_val_5", mn.Quaternion.rotation(mn.Deg(90.0), [-1.0, 0.0, 0.0]))
    assert config.get_as_string("obj_val_1") == "17"
    assert config.get_as_string("obj_val_2") == "False"
    assert config.get_as_string("obj_val_3") == "19.7"
    assert config.get_as_string("obj_val_4") == "[2.5 0 0.2]"
    assert config.get_as_string("obj_val_5") == "0.707107 [-0.707107 0 0]"
    assert config.get_as_string("obj_val_0").startswith("This is")


def test_types_and_keys_by_type():
    config = Configuration()
    config.set("flag", True)
    config.set("count", 3)
    config.set("ratio", 0.5)
    config.set("where", np.array([1.0, 2.0, 3.0]))
    assert config.get_type("flag") is ConfigValType.Boolean  # bool is not stored as int
    assert config.get_keys_by_type(ConfigValType.Integer) == ["count"]
    assert config.get_keys_by_type(float) == ["ratio"]
    assert isinstance(config.get("where"), mn.Vector3)


def test_get_returns_copies_and_remove_works():
    config = Configuration()
    config.set("v", [1, 2, 3])
    v = config.get("v")
    v.x = 10
    assert config.get("v") == [1, 2, 3]
    assert config.remove("v") == [1, 2, 3]
    assert not config.has_value("v")
    with pytest.raises(KeyError):
        config.get("v")


def test_subconfigs_are_editable_in_place_and_copied_on_copy():
    config = Configuration.from_dict({"outer": {"inner": 1.5, "pos": [1, 2, 3]}, "top": "x"})
    sub = config.get_subconfig("outer")
    assert sub.get("inner") == 1.5
    sub.set("inner", 2.5)
    assert config.get_subconfig("outer").get("inner") == 2.5
    clone = config.copy()
    clone.get_subconfig("outer").set("inner", 9.0)
    assert config.get_subconfig("outer").get("inner") == 2.5


def test_unsupported_values_raise_naming_the_key():
    config = Configuration()
    with pytest.raises(ValueError, match="bad"):
        config.set("bad", {"a": 1})
    with pytest.raises(ValueError):
        config.set("", 1)
    with pytest.raises(ValueError, match="nanvec"):
        config.set("nanvec", [np.nan, 0, 0])
