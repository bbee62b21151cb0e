"""``SensorFactory`` and the sensor views of scene nodes, after Habitat-sim's own tests.

Habitat's ``src/tests/SensorTest.cpp`` (``testSensorFactory``, ``testSensorDestructors``)
creates sensors on a small tree of nodes and counts ``node_sensors`` (the sensors on a node's
leaf children) and ``subtree_sensors`` (everything below) at every node after each creation
and deletion; its ``tests/test_agent.py::test_sensor_subtree_discovery`` checks that
``agent.sensors`` follows a sensor created on, then deleted from, a child of the agent's node.
The counts below are Habitat's.
"""

from __future__ import annotations

import logging

import pytest

import engine as habitat_sim
from engine.sensor import SensorFactory


def camera(uuid: str) -> habitat_sim.CameraSensorSpec:
    spec = habitat_sim.CameraSensorSpec()
    spec.uuid = uuid
    spec.resolution = [8, 8]
    return spec


def counts(*nodes) -> list[tuple[int, int]]:
    """(len(node_sensors), len(subtree_sensors)) of each node."""
    return [(len(node.node_sensors), len(node.subtree_sensors)) for node in nodes]


def test_create_sensors_counts_as_habitats_sensor_factory_test():
    root = habitat_sim.SceneGraph().get_root_node()
    parent = root.create_child()
    child = parent.create_child()
    returned = SensorFactory.create_sensors(parent, [camera("A"), camera("B")])
    assert counts(root, parent) == [(0, 2), (2, 2)]
    assert set(returned) == {"A", "B"}  # Habitat returns the node's sensors
    SensorFactory.create_sensors(parent, [camera("C")])
    assert counts(root, parent) == [(0, 3), (3, 3)]
    returned = SensorFactory.create_sensors(child, [camera("D"), camera("E")])
    assert counts(root, parent, child) == [(0, 5), (3, 5), (2, 2)]
    assert set(returned) == {"D", "E"}
    # the same uuid twice on one node: one sensor more, the first one kept
    twice = camera("F")
    returned = SensorFactory.create_sensors(parent, [twice, twice])
    assert counts(root, parent, child) == [(0, 6), (4, 6), (2, 2)]
    assert set(returned) == {"A", "B", "C", "F"}
    first_f = min(
        (node.own_sensors["F"] for node in parent.children if "F" in node.own_sensors),
        key=lambda sensor: sensor.creation_order,
    )
    assert parent.node_sensors["F"] is first_f and root.subtree_sensors["F"] is first_f


def test_delete_subtree_sensor_counts_as_habitats_sensor_destructors_test():
    root = habitat_sim.SceneGraph().get_root_node()
    parent = root.create_child()
    child = parent.create_child()
    grandchild = child.create_child()
    grandchild2 = child.create_child()
    greatgrandchild = grandchild.create_child()
    nodes = (root, parent, child, grandchild, grandchild2, greatgrandchild)
    SensorFactory.create_sensors(parent, [camera("1A"), camera("1B")])
    SensorFactory.create_sensors(child, [camera(f"2{c}") for c in "ABC"])
    SensorFactory.create_sensors(grandchild, [camera(f"3{c}") for c in "ABCD"])
    SensorFactory.create_sensors(grandchild2, [camera("4A"), camera("4B")])
    SensorFactory.create_sensors(greatgrandchild, [camera("5A"), camera("5B")])
    assert counts(*nodes) == [(0, 13), (2, 13), (3, 11), (4, 6), (2, 2), (2, 2)]
    SensorFactory.delete_subtree_sensor(parent, "1A")
    assert counts(*nodes) == [(0, 12), (1, 12), (3, 11), (4, 6), (2, 2), (2, 2)]
    SensorFactory.delete_subtree_sensor(parent, "2A")
    assert counts(*nodes) == [(0, 11), (1, 11), (2, 10), (4, 6), (2, 2), (2, 2)]
    SensorFactory.delete_subtree_sensor(parent, "3A")
    assert counts(*nodes) == [(0, 10), (1, 10), (2, 9), (3, 5), (2, 2), (2, 2)]
    SensorFactory.delete_subtree_sensor(parent, "5A")
    assert counts(*nodes) == [(0, 9), (1, 9), (2, 8), (3, 4), (2, 2), (1, 1)]
    # a whole subtree removed from the graph takes its sensors with it
    grandchild.parent = None
    assert counts(root, parent, child) == [(0, 5), (1, 5), (2, 4)]


def test_deleting_a_missing_sensor_is_logged_and_changes_nothing(caplog):
    node = habitat_sim.SceneGraph().get_root_node().create_child()
    SensorFactory.create_sensors(node, [camera("kept")])
    other = node.create_child()
    with caplog.at_level(logging.DEBUG, logger=SensorFactory.__module__):
        SensorFactory.delete_subtree_sensor(other, "kept")  # not below `other`
        SensorFactory.delete_subtree_sensor(node, "missing")
    assert list(node.subtree_sensors) == ["kept"]
    assert "'missing'" in caplog.text and "'kept'" in caplog.text


def test_agent_sensors_follow_sensors_added_and_removed_below_the_agent():
    scene_graph = habitat_sim.SceneGraph()
    agent_node = scene_graph.get_root_node().create_child()
    agent = habitat_sim.Agent(agent_node)
    initial_count = len(agent.sensors)
    child_node = agent_node.create_child()
    SensorFactory.create_sensors(child_node, [camera("extra_rgb")])
    assert "extra_rgb" in agent.sensors and len(agent.sensors) == initial_count + 1
    assert agent._sensors["extra_rgb"] is agent.sensors["extra_rgb"]
    SensorFactory.delete_subtree_sensor(child_node, "extra_rgb")
    assert "extra_rgb" not in agent.sensors and len(agent.sensors) == initial_count
    # a sensor on a node elsewhere in the graph is not the agent's
    SensorFactory.create_sensors(scene_graph.get_root_node().create_child(), [camera("wall")])
    assert "wall" not in agent.sensors


def test_bad_input_creates_no_sensor():
    node = habitat_sim.SceneGraph().get_root_node().create_child()
    with pytest.raises(TypeError, match="SensorSpec"):
        SensorFactory.create_sensors(node, [camera("ok"), "not a spec"])
    with pytest.raises(TypeError, match="SceneNode"):
        SensorFactory.create_sensors("not a node", [camera("ok")])
    assert not node.subtree_sensors and not node.children
