"""A Nav2 parameter file's controller_server section read as our server's settings (pure
Python): limits under each Nav2 controller's names, our controllers' tunings, the checkers, and
what cannot be honoured refused by name."""

import pytest

from turtle_traj.api.controllers import choose, from_plugin_name
from turtle_traj.core.control.controllers.catalogue import parameter_prefix
from turtle_traj.core.parameters.nav2_file import Nav2ConfigError, read_server_section


def read(values):
    return read_server_section(values, controller_name=from_plugin_name,
                               tunables=lambda name: choose(name).tunables,
                               prefix=parameter_prefix)


def test_defaults_as_nav2s_and_limits_under_dwbs_names():
    config = read({'FollowPath.plugin': 'turtle_traj::PurePursuit', 'FollowPath.max_vel_x': 0.26,
                   'FollowPath.acc_lim_x': 2.5, 'FollowPath.decel_lim_x': -2.0,
                   'FollowPath.lookahead_time': 2.0, 'FollowPath.path_tolerance': 0.05})
    assert dict(config.controllers) == {'FollowPath': 'pure_pursuit'}
    parameters = config.node_parameters
    assert (parameters['linear_speed'], parameters['max_linear_accel'],
            parameters['max_linear_decel']) == (0.26, 2.5, 2.0)
    assert parameters['pure_pursuit.lookahead_time'] == 2.0  # its Tunable, by its own name
    assert parameters['path_tolerance'] == 0.05  # how far its goals' paths may be smoothed
    assert parameters['control_rate'] == 20.0 and parameters['cmd_vel_type'] == 'Twist'
    assert list(config.goal_checkers) == ['goal_checker']  # Nav2's default ids
    assert config.speed_limit_topic == 'speed_limit' and config.ignored == ()


def test_a_users_own_class_by_module_and_class():
    config = read({'FollowPath.plugin': 'tests.misbehaving_controllers:StopsHalfWay'})
    assert config.controllers['FollowPath'] == 'tests.misbehaving_controllers:StopsHalfWay'


@pytest.mark.parametrize(('values', 'said'), [
    ({'controller_plugins': ['A', 'B'], 'A.plugin': 'turtle_traj::Dwpp', 'A.vx_max': 0.5,
      'B.plugin': 'turtle_traj::ExactFollower', 'B.vx_max': 0.3},
     'B.vx_max is 0.3, but another controller id sets linear_speed to 0.5'),
    ({'controller_plugins': 'FollowPath', 'FollowPath.plugin': 'turtle_traj::Dwpp'},
     "controller_plugins must be a non-empty list of ids, not 'FollowPath'"),
    ({'controller_plugins': ['FollowPath']}, 'FollowPath.plugin is not set'),
    ({'FollowPath.plugin': 'turtle_traj::Dwpp', 'FollowPath.vx_max': 'fast'},
     "FollowPath.vx_max must be a number, not 'fast'"),
    ({'FollowPath.plugin': 'turtle_traj::Dwpp', 'enable_stamped_cmd_vel': 'yes'},
     "enable_stamped_cmd_vel must be true or false, not 'yes'"),
    ({'FollowPath.plugin': 'turtle_traj::Dwpp', 'progress_checker.plugin':
      'nav2_controller::PoseProgressChecker'}, 'is not a checker this server has'),
    ({'FollowPath.plugin': 'turtle_traj::Dwpp', 'FollowPath.max_lookahead_dist': float('nan')},
     'FollowPath.max_lookahead_dist is nan'),
])
def test_what_cannot_be_honoured_is_refused_by_name(values, said):
    with pytest.raises(Nav2ConfigError) as refused:
        read(values)
    assert said in str(refused.value)


def test_goal_checkers_as_nav2_states_them():
    from turtle_traj.core.control.goal_check import GoalChecker, checker_for
    from turtle_traj.core.geometry.path import Pose2D
    config = read({'FollowPath.plugin': 'turtle_traj::Dwpp',
                   'goal_checker_plugins': ['loose', 'stopped'],
                   'loose.plugin': 'nav2_controller::SimpleGoalChecker',
                   'loose.xy_goal_tolerance': 0.1, 'loose.stateful': True,
                   'stopped.plugin': 'nav2_controller::StoppedGoalChecker',
                   'stopped.trans_stopped_velocity': 0.05})
    loose, stopped = config.goal_checkers['loose'], config.goal_checkers['stopped']
    assert config.ignored == ()  # stateful is read (a check made once needs no state)
    assert (loose.xy_tolerance, loose.yaw_tolerance, loose.stopped) == (0.1, 0.25, None)
    at = Pose2D(1.0, 0.0, 0.2)
    assert loose.miss(at, (0.0, 0.0), (1.05, 0.0), 0.0) is None
    assert loose.miss(at, (0.0, 0.0), (1.2, 0.0), 0.0) == (
        'goal checker loose: 0.200 m from the goal, beyond xy_goal_tolerance 0.1 m')
    assert 'beyond yaw_goal_tolerance 0.25 rad' in loose.miss(at, (0.0, 0.0), (1.0, 0.0), -0.1)
    assert loose.miss(at, (0.0, 0.0), (1.0, 0.0), None) is None  # no orientation: any heading
    assert stopped.stopped == (0.05, 0.25)
    assert 'still moving at 0.100 m/s' in stopped.miss(at, (0.1, 0.0), (1.0, 0.0), 0.2)
    assert checker_for(config.goal_checkers, 'stopped') is stopped
    with pytest.raises(KeyError, match="goal_checker_id '' is not one of this server's"):
        checker_for(config.goal_checkers, '')  # empty picks the only one, not one of two
    assert checker_for({'only': loose}, '') is loose
    with pytest.raises(ValueError, match='loose.xy_goal_tolerance must be a number of at least'):
        GoalChecker.from_values('loose', 'nav2_controller::SimpleGoalChecker',
                                {'xy_goal_tolerance': -1.0})
