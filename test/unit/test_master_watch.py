"""Unit tests for rbx1_nav.common.master_watch (no ROS master needed)."""
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rbx1_nav.common.master_watch import (BACK, GONE, GONE_AFTER, RESTARTED,
                                          MasterStates, gone_text, misdirected_text,
                                          replaced_node, restarted_text,
                                          reregistering_text, same_master)

OLD, NEW = (101, 'run-a'), (202, 'run-b')  # (pid, run_id) of two masters


def events(observations, gone_after=GONE_AFTER):
    states = MasterStates(gone_after)
    return [states.observe(identity) for identity in observations]


def test_the_same_master_answering_is_nothing_to_report():
    assert events([OLD] * 5) == [None] * 5


def test_gone_only_after_three_failed_polls_in_a_row_and_once():
    assert events([OLD, None, None, None, None, None]) == [
        None, None, None, GONE, None, None]


def test_a_lossy_link_never_reports_gone():
    # Two polls in three lost, forever: never three failures in a row.
    assert events([OLD] + [None, None, OLD] * 10) == [None] * 31


def test_the_same_master_after_gone_is_back_once():
    assert events([OLD, None, None, None, OLD, OLD]) == [
        None, None, None, GONE, BACK, None]


def test_the_same_master_after_a_short_outage_is_nothing_to_report():
    assert events([OLD, None, None, OLD]) == [None] * 4


def test_a_quick_restart_is_reported_without_gone():
    # roscore restarted between two polls, or within fewer than three.
    assert events([OLD, NEW]) == [None, RESTARTED]
    assert events([OLD, None, NEW, NEW]) == [None, None, RESTARTED, None]


def test_a_restart_after_gone_is_reported_as_restarted_not_back():
    assert events([OLD, None, None, None, NEW, NEW]) == [
        None, None, None, GONE, RESTARTED, None]


def test_after_a_restart_the_new_master_is_the_reference():
    assert events([OLD, NEW, None, None, None, NEW, OLD]) == [
        None, RESTARTED, None, None, GONE, BACK, RESTARTED]


def test_a_master_unreachable_from_the_start_cannot_be_told_restarted():
    # Nothing seen before: the first master seen is the reference.
    assert events([None, None, None, OLD, NEW]) == [
        None, None, GONE, BACK, RESTARTED]
    assert events([None, OLD, OLD]) == [None, None, None]


def test_a_pid_reused_by_a_new_run_is_still_a_restart():
    # A master restarted in a container often gets the same pid again.
    assert events([(7, 'run-a'), (7, 'run-b')]) == [None, RESTARTED]


def test_a_new_roscore_is_seen_before_and_after_it_sets_its_run_id():
    # roscore's master answers a moment before roslaunch sets /run_id: one
    # restart, not two.
    assert events([OLD, (202, None), NEW, NEW]) == [None, RESTARTED, None, None]


def test_a_master_without_run_id_is_told_by_its_pid():
    # A bare rosmaster never sets /run_id.
    assert events([(101, None), (101, None), (202, None)]) == [
        None, None, RESTARTED]


def test_a_missing_run_id_does_not_make_the_reference_forget_its_own():
    # Same pid, run_id not (yet) read, then a different run_id: a
    # container's quick restart, caught on the poll after.
    assert events([(7, 'run-a'), (7, None), (7, 'run-b')]) == [
        None, None, RESTARTED]


def test_same_master_compares_pids_and_known_run_ids():
    assert same_master((1, 'a'), (1, 'a'))
    assert same_master((1, None), (1, 'a')) and same_master((1, 'a'), (1, None))
    assert not same_master((1, 'a'), (1, 'b'))
    assert not same_master((2, 'a'), (1, 'a'))
    assert not same_master((2, None), (1, None))


def test_gone_after_is_configurable_and_checked():
    assert events([OLD, None], gone_after=1) == [None, GONE]
    with pytest.raises(ValueError):
        MasterStates(0)


@given(st.lists(st.sampled_from([None, OLD, NEW, (101, None), (202, None)]),
                max_size=60))
def test_gone_and_its_end_alternate_and_gone_needs_three_failures(observations):
    got = events(observations)
    # GONE is always followed by BACK or RESTARTED before the next GONE,
    # and BACK only ever follows GONE.
    said = [event for event in got if event is not None]
    for first, second in zip([None] + said, said):
        assert not (first == GONE and second == GONE)
        assert not (second == BACK and first != GONE)
    for i, event in enumerate(got):
        if event == GONE:
            assert observations[max(0, i - GONE_AFTER + 1):i + 1] == \
                [None] * GONE_AFTER
        if event in (BACK, RESTARTED):
            assert observations[i] is not None


def test_the_texts_name_the_node_the_master_and_the_fix():
    uri = 'http://robot:11311'
    text = restarted_text('odom_out_and_back', uri)
    assert text.startswith('odom_out_and_back: the ROS master at ' + uri)
    assert 'restarted' in text and 'Fix: restart this node' in text
    assert 'RViz' in reregistering_text('pose_ekf', uri)
    assert 'connection refused' in gone_text('pose_ekf', uri, 'connection refused')


def test_the_master_s_request_to_a_replaced_node_names_it():
    # rosmaster.registrations.shutdown_node_task's words.
    assert replaced_node('[/calibrate_linear] Reason: new node registered with '
                         'same name') == '/calibrate_linear'
    assert replaced_node('[/ns/robot_1] Reason: new node registered with same '
                         'name') == '/ns/robot_1'
    # Other requests name nobody: rosnode kill's, an empty one.
    for msg in ('user request', '', None, '[/x] Reason: something else'):
        assert replaced_node(msg) is None


def test_a_refused_shutdown_names_both_nodes_and_the_cause():
    text = misdirected_text('/fake_turtlebot', '/calibrate_linear')
    assert text.startswith('/fake_turtlebot: ')
    assert '/calibrate_linear' in text and 'ros_comm#2241' in text
