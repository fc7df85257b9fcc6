"""3-D views and animations of rmpc's robots on Pinocchio's ``MeshcatVisualizer`` (also ``rmpc.viewer``).

``show(robot, q)``, ``animate(robot, motion)``, ``export_html(robot, motion, path)`` (one page, no server, no
network); what to draw beside the robot for the chapters' tasks (:mod:`viewer.views`): ``contact_animation``
(Ch. 9), ``eye_in_hand_animation`` (Ch. 10), ``box_overlays`` and ``frame_path`` (Ch. 12); mobile robots
``planar_body``, ``plane_camera`` (Ch. 11, 12). Imported by notebooks, examples and the report — never by
``rigid_body``, ``planners`` or ``controllers``.

>>> from rigid_body.robots import load
>>> robot = load("planar_2r")
>>> scene = show(robot, [0.3, -0.6])          # inline in a notebook; scene.save("pose.html")
>>> from planners.timing import quintic
>>> traj = quintic([0.0, 0.0], [1.0, -1.0], 1.0, dt=0.01)
>>> path = export_html(robot, traj, "/tmp/rmpc-doctest-2r.html")   # one offline HTML file
"""

from viewer.animation import animate, default_camera, export_html, motion_of, report_animations, show, up_rotation
from viewer.geometry import geometry_of, skeleton_of
from viewer.mobile import planar_body, plane_camera
from viewer.pendant import TeachPendant
from viewer.scene import Scene, arrow_transform
from viewer.views import box_overlays, contact_animation, eye_in_hand_animation, frame_path

__all__ = ["Scene", "TeachPendant", "animate", "arrow_transform", "box_overlays", "contact_animation", "default_camera",
           "export_html", "eye_in_hand_animation", "frame_path", "geometry_of", "motion_of", "planar_body",
           "plane_camera", "report_animations", "show", "skeleton_of", "up_rotation"]
