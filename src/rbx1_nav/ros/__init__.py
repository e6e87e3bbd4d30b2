"""The ROS side shared by the package's nodes (these modules import rospy).

The behaviour lives in the rospy-free modules of ``rbx1_nav``; the modules
here wire it to topics, tf and parameters once, for every node.
"""
