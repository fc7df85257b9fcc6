"""A teach pendant: one slider per joint moving the robot in a live viewer (ipywidgets in a notebook)."""

from __future__ import annotations

from typing import Any

import numpy as np

from rigid_body.robots import Robot
from rigid_body.validation import as_vector
from viewer.animation import show
from viewer.scene import Scene, as_robot


class TeachPendant:
    """Joint sliders for ``robot`` driving ``scene`` (a live meshcat server on 127.0.0.1 by default).

    ``pendant.set(j, value)`` moves joint j (what a slider does); ``pendant.widget()`` builds the
    ipywidgets panel: the sliders next to the live viewer.
    """

    def __init__(self, robot: Robot | str, q: Any | None = None, scene: Scene | None = None, server: bool = True):
        robot = as_robot(robot)
        if robot.nq != robot.nv:
            raise ValueError(f"robot {robot.name!r}: the pendant moves joints with one coordinate each (nq == nv)")
        self.robot = robot
        self.q = as_vector(robot.configurations["neutral"] if q is None else q, robot.nq, "q").copy()
        self.lower = np.maximum(robot.lower, -np.pi)
        self.upper = np.minimum(robot.upper, np.pi)
        self.scene = show(robot, self.q, server=server) if scene is None else scene
        if scene is not None:
            self.scene.add_robot(robot, self.q)

    def set(self, joint: int, value: float) -> np.ndarray:
        """Move joint ``joint`` (0-based) to ``value`` (clipped to its limits); return q."""
        if not 0 <= joint < self.robot.nq:
            raise ValueError(f"`joint` must be in [0, {self.robot.nq}), got {joint}")
        self.q[joint] = float(np.clip(value, self.lower[joint], self.upper[joint]))
        self.scene.display(self.q)
        return self.q.copy()

    def widget(self) -> Any:
        """The panel: a slider per joint (named after the URDF joints) and the viewer."""
        import ipywidgets as widgets

        names = [n for j, n in enumerate(self.robot.model.names) if j > 0][: self.robot.nq]
        sliders = []
        for j in range(self.robot.nq):
            slider = widgets.FloatSlider(value=self.q[j], min=self.lower[j], max=self.upper[j], step=0.01,
                                         description=names[j] if j < len(names) else f"q{j + 1}",
                                         continuous_update=True)
            slider.observe(lambda change, j=j: self.set(j, change["new"]), names="value")
            sliders.append(slider)
        url = self.scene.url
        view = widgets.HTML(f'<iframe src="{url}" style="width:100%;height:420px;border:none"></iframe>'
                            if url else self.scene._repr_html_())
        return widgets.VBox([view, *sliders])
