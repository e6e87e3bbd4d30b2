"""test/helpers/ros_etc.py: the suite's /etc/ros gives every launch the
parameters the original's commands give, without running them."""
import os

import roslaunch.config

import ros_etc

ROSCORE = '''<launch>
  <group ns="/">
    <param name="said" command="printf 'one two\\n'"/>
    <param name="number" command="echo 7"/>
    <param name="plain" value="kept"/>
    <node pkg="rosout" type="rosout" name="rosout" respawn="true"/>
  </group>
</launch>
'''


def launch_params(monkeypatch, etc):
    monkeypatch.setenv('ROS_ETC_DIR', str(etc))
    config = roslaunch.config.load_config_default([], None, verbose=False)
    return {name: param.value for name, param in config.params.items()}, config.nodes_core


def test_answered_roscore_gives_the_same_parameters_and_nodes(tmp_path, monkeypatch):
    source, target = tmp_path / 'etc', tmp_path / 'answered'
    source.mkdir()
    target.mkdir()
    (source / 'roscore.xml').write_text(ROSCORE)
    (source / 'python_logging.conf').write_text('[loggers]\n')
    ros_etc.answered_etc(str(source), str(target))

    original, original_nodes = launch_params(monkeypatch, source)
    answered, answered_nodes = launch_params(monkeypatch, target)
    assert original == {'/said': 'one two\n', '/number': 7, '/plain': 'kept'}, original
    assert answered == original
    assert [n.type for n in answered_nodes] == [n.type for n in original_nodes] == ['rosout']
    # No command left to run; the rest of the directory is the original's.
    assert 'command=' not in (target / 'roscore.xml').read_text()
    assert os.path.realpath(str(target / 'python_logging.conf')) == str(
        source / 'python_logging.conf')


def test_a_directory_without_commands_is_used_as_it_is(tmp_path, monkeypatch):
    (tmp_path / 'roscore.xml').write_text('<launch><param name="a" value="1"/></launch>')
    monkeypatch.setenv('ROS_ETC_DIR', str(tmp_path))
    ros_etc.use_answered_etc()
    assert os.environ['ROS_ETC_DIR'] == str(tmp_path)


def test_a_command_that_fails_leaves_the_directory_as_it_was(tmp_path, monkeypatch):
    (tmp_path / 'roscore.xml').write_text(
        '<launch><param name="a" command="no_such_command_here"/></launch>')
    monkeypatch.setenv('ROS_ETC_DIR', str(tmp_path))
    ros_etc.use_answered_etc()
    assert os.environ['ROS_ETC_DIR'] == str(tmp_path)
