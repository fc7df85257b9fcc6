"""The two-link arm with motors and a tip payload in closed form, Eq. (7.82) + [ARM2L] of the spec.

An independent reference for the controllers' tests (no Pinocchio): data of Sect. 7.3.2 / param.m.
"""

import numpy as np

A1 = A2 = 1.0
L1 = L2 = 0.5
M_L1 = M_L2 = 50.0
I_L1 = I_L2 = 10.0
K_R1 = K_R2 = 100.0
M_M2 = 5.0
I_M1 = I_M2 = 0.01
G = 9.81


def inertia(q, m_L=0.0):
    c2 = np.cos(q[1])
    b11 = (I_L1 + M_L1 * L1**2 + K_R1**2 * I_M1 + I_L2 + M_L2 * (A1**2 + L2**2 + 2 * A1 * L2 * c2) + I_M2
           + M_M2 * A1**2 + m_L * (A1**2 + A2**2 + 2 * A1 * A2 * c2))
    b12 = I_L2 + M_L2 * (L2**2 + A1 * L2 * c2) + K_R2 * I_M2 + m_L * (A2**2 + A1 * A2 * c2)
    b22 = I_L2 + M_L2 * L2**2 + K_R2**2 * I_M2 + m_L * A2**2
    return np.array([[b11, b12], [b12, b22]])


def coriolis(q, qd, m_L=0.0):
    h = -(M_L2 * A1 * L2 + m_L * A1 * A2) * np.sin(q[1])
    return np.array([[h * qd[1], h * (qd[0] + qd[1])], [-h * qd[0], 0.0]])


def gravity(q, m_L=0.0):
    c1, c12 = np.cos(q[0]), np.cos(q[0] + q[1])
    g2 = (M_L2 * L2 + m_L * A2) * G * c12
    return np.array([(M_L1 * L1 + M_M2 * A1 + M_L2 * A1 + m_L * A1) * G * c1 + g2, g2])


def tip(q):
    return np.array([A1 * np.cos(q[0]) + A2 * np.cos(q[0] + q[1]), A1 * np.sin(q[0]) + A2 * np.sin(q[0] + q[1])])


def jacobian(q):
    s1, c1, s12, c12 = np.sin(q[0]), np.cos(q[0]), np.sin(q[0] + q[1]), np.cos(q[0] + q[1])
    return np.array([[-A1 * s1 - A2 * s12, -A2 * s12], [A1 * c1 + A2 * c12, A2 * c12]])


def jacobian_derivative_times_qd(q, qd):
    w1, w12 = qd[0], qd[0] + qd[1]
    return np.array([-A1 * np.cos(q[0]) * w1**2 - A2 * np.cos(q[0] + q[1]) * w12**2,
                     -A1 * np.sin(q[0]) * w1**2 - A2 * np.sin(q[0] + q[1]) * w12**2])


def forward_dynamics(q, qd, tau, m_L=0.0):
    return np.linalg.solve(inertia(q, m_L), tau - coriolis(q, qd, m_L) @ qd - gravity(q, m_L))
