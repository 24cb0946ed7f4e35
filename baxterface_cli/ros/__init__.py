"""ROS 1 adapters: the face node, `send` and `stream`. Only these import rospy."""
