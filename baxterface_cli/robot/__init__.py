"""The robot's side, without ROS: the rules between effects and the robot, with the clock passed in.

robot_rules (head only while enabled, retries, following), following (where to look for a
person or a hand), person_finder, mtcnn_detector (MTCNN), haar_detector (Haar), person_choice and
camera_watch (a person's face in the head camera, from 24 pixels wide),
navigator_buttons (Baxter's buttons as face commands), rehearsal (a recorded trace or camera
images in place of the sensors: `--follow-from`).
"""
