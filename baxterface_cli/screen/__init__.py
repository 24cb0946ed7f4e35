"""The screen: the face alone, for any screen with a browser, served through the web room's face API.

screen_face (the node's live face without ROS or the web), screen_api (its routes),
chatter_feed (`--ros`: commands heard on display_chatter).
"""
