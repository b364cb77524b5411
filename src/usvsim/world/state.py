"""Kinematic state of the floating bodies, refreshed in place after every physics step by the `World`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class BodyState:
    """Kinematics of all floating bodies at the current time (world ENU unless named _body)."""

    n: int
    pos: np.ndarray = field(init=False)
    rot: np.ndarray = field(init=False)
    com_world: np.ndarray = field(init=False)
    vcom_world: np.ndarray = field(init=False)
    omega_body: np.ndarray = field(init=False)
    nu: np.ndarray = field(init=False)

    def __post_init__(self):
        n = self.n
        self.pos, self.rot, self.com_world = np.zeros((n, 3)), np.zeros((n, 3, 3)), np.zeros((n, 3))
        self.vcom_world, self.omega_body, self.nu = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 6))
