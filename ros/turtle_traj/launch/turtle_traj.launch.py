"""Simulator and trajectory node: `ros2 launch turtle_traj turtle_traj.launch.py`.

Arguments: time_scale (our simulator only; != 1 makes both nodes follow its /clock), gui,
web (our simulator's live view in a browser, on web_host:web_port), turtle_name, namespace,
use_real_turtlesim:=true (starts turtlesim's turtlesim_node instead of ours, at real time).
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration, PythonExpression
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    time_scale = LaunchConfiguration('time_scale')
    gui = LaunchConfiguration('gui')
    web = LaunchConfiguration('web')
    real = LaunchConfiguration('use_real_turtlesim')
    namespace = LaunchConfiguration('namespace')
    ours = ["'", real, "'.lower() != 'true'"]
    scaled = PythonExpression([*ours, ' and float(', time_scale, ') != 1.0'])
    sim_parameters = [{'time_scale': time_scale, 'publish_clock': scaled}]

    def flag(name: str, value: LaunchConfiguration) -> PythonExpression:
        """--name or --no-name, as the launch argument says."""
        return PythonExpression([f"'--{name}' if '", value, f"'.lower() == 'true' else "
                                 f"'--no-{name}'"])
    return LaunchDescription([
        DeclareLaunchArgument('time_scale', default_value='1.0',
                              description='our simulator: times faster than real time'),
        DeclareLaunchArgument('gui', default_value='false',
                              description='our simulator: show its window (pygame)'),
        DeclareLaunchArgument('web', default_value='false',
                              description='our simulator: serve its live view to a browser'),
        DeclareLaunchArgument('web_host', default_value='127.0.0.1',
                              description='our simulator: address of the live view'),
        DeclareLaunchArgument('web_port', default_value='8080',
                              description='our simulator: port of the live view'),
        DeclareLaunchArgument('turtle_name', default_value='turtle1',
                              description='the turtle the node drives'),
        DeclareLaunchArgument('namespace', default_value='',
                              description='namespace of both nodes (e.g. sim1)'),
        DeclareLaunchArgument('use_real_turtlesim', default_value='false',
                              description='start turtlesim turtlesim_node instead of ours'),
        Node(package='turtle_traj', executable='sim', name='turtlesim', namespace=namespace,
             parameters=sim_parameters, output='screen',
             arguments=[flag('gui', gui), flag('web', web),
                        '--web-host', LaunchConfiguration('web_host'),
                        '--web-port', LaunchConfiguration('web_port')],
             condition=IfCondition(PythonExpression(ours))),
        Node(package='turtlesim', executable='turtlesim_node', name='turtlesim',
             namespace=namespace, output='screen', condition=IfCondition(real)),
        Node(package='turtle_traj', executable='trajectory_node', name='turtle_traj',
             namespace=namespace, output='screen',
             parameters=[{'turtle_name': LaunchConfiguration('turtle_name'),
                          'use_sim_time': scaled}]),
    ])
