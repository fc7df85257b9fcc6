"""Joint actuators: the DC servomotor with its power amplifier and current loop, the hydraulic motor.

The electric servomotor follows the block scheme of Fig. 5.2: the armature circuit
``I_a = (V_a − k_v Ω_m)/(R_a + s L_a)`` (5.1)–(5.2), the motor torque ``C_m = k_t I_a`` (5.3), the rotor
``Ω_m = (C_m − C_r)/(s I_m + F_m)`` (5.4), a power amplifier ``V_a = G_v/(1 + s T_v) · V_c`` driven by
the current regulator ``V_c = C_i(s)(V'_c − k_i I_a)``. Two views of the same physics are provided,
built independently so that each checks the other:

* :func:`servomotor_transfer_functions`: python-control transfer functions obtained by block
  reduction of Fig. 5.2 (``control.feedback`` on the blocks);
* :class:`controllers.plants.ServomotorPlant`: the same equations written as a state-space ODE
  ``derivative(t, x, u)`` for :func:`controllers.simulation.simulate`.

The hydraulic motor with servovalve and distributor of Sect. 5.1 is given as transfer functions by
block reduction of Fig. S5.5 (:func:`hydraulic_transfer_functions`).

References: Siciliano et al., *Robotics: Modelling, Planning and Control*, Springer 2009,
Sect. 5.1 (Eqs. (5.1)–(5.8), Figs. 5.2–5.4), Problems 5.1–5.4.
"""

from __future__ import annotations

from dataclasses import dataclass

import control
import numpy as np

from rigid_body.validation import as_positive, as_vector


@dataclass(frozen=True)
class PIRegulator:
    """C(s) = K (1 + s T)/s: a proportional–integral regulator in the book's form (Problems 5.3 and 8.1)."""

    K: float
    T: float

    def __post_init__(self) -> None:
        as_positive(self.K, "K")
        as_positive(self.T, "T", allow_zero=True)

    def tf(self) -> control.TransferFunction:
        return control.tf([self.K * self.T, self.K], [1.0, 0.0])


@dataclass(frozen=True)
class DCServomotor:
    """A permanent-magnet DC servomotor with power amplifier (Sect. 5.1, Fig. 5.2).

    Attributes (SI): ``Ra`` [Ω], ``La`` [H], ``kt`` [N·m/A], ``kv`` [V·s/rad], ``Im`` [kg·m²],
    ``Fm`` [N·m·s/rad], amplifier gain ``Gv`` and time constant ``Tv`` [s], current transducer ``ki``
    [V/A] (0: no current feedback, the velocity-controlled generator of Fig. 5.3).
    """

    Ra: float
    La: float
    kt: float
    kv: float
    Im: float
    Fm: float
    Gv: float = 1.0
    Tv: float = 0.0
    ki: float = 0.0

    def __post_init__(self) -> None:
        for name in ("Ra", "kt", "kv", "Im", "Gv"):
            as_positive(getattr(self, name), name)
        for name in ("La", "Fm", "Tv", "ki"):
            as_positive(getattr(self, name), name, allow_zero=True)

    @property
    def mechanical_time_constant(self) -> float:
        """T_m = R_a I_m/(k_v k_t): the rotor time constant with back-emf damping (F_m neglected)."""
        return self.Ra * self.Im / (self.kv * self.kt)

    def steady_state(self, v_c: float, c_r: float = 0.0, K: float = 1.0) -> tuple[float, float]:
        """(ω_m, i_a) at steady state for a constant V'_c and load C_r, Eqs. (S5.1)–(S5.5), K = C_i(0) G_v.

        Solves ``K v'_c = (R_a + K k_i) i_a + k_v ω_m`` and ``k_t i_a = F_m ω_m + c_r``.
        """
        v_c, c_r = float(as_vector(v_c, 1, "v_c")[0]), float(as_vector(c_r, 1, "c_r")[0])
        K = as_positive(K, "K")
        A = np.array([[self.kv, self.Ra + K * self.ki], [-self.Fm, self.kt]])
        omega, i_a = np.linalg.solve(A, [K * v_c, c_r])
        return float(omega), float(i_a)


def _regulator_tf(regulator: PIRegulator | float) -> control.TransferFunction:
    if isinstance(regulator, PIRegulator):
        return regulator.tf()
    return control.tf([as_positive(regulator, "regulator")], [1.0])


@dataclass(frozen=True)
class ServomotorTransferFunctions:
    """Closed-loop transfer functions of Fig. 5.2 (inputs V'_c, C_r; outputs Ω_m, I_a)."""

    velocity_input: control.TransferFunction     # Ω_m/V'_c
    velocity_load: control.TransferFunction      # Ω_m/C_r
    current_input: control.TransferFunction      # I_a/V'_c
    current_load: control.TransferFunction       # I_a/C_r


def servomotor_transfer_functions(motor: DCServomotor, regulator: PIRegulator | float = 1.0
                                  ) -> ServomotorTransferFunctions:
    """Block reduction of Fig. 5.2 with python-control.

    Parameters
    ----------
    motor : the motor and amplifier data.
    regulator : C_i(s): a :class:`PIRegulator` or a constant gain (C_i(0) G_v = K of (5.7)).
    """
    s = control.tf("s")
    armature = 1 / (motor.La * s + motor.Ra)                   # (5.1)
    rotor = 1 / (motor.Im * s + motor.Fm)                      # (5.4)
    amplifier = motor.Gv / (motor.Tv * s + 1)                  # G_v/(1 + s T_v)
    Ci = _regulator_tf(regulator)
    # Current loop with the back-emf input cut: I_a = A(s)(C_i G (V'_c − k_i I_a) − k_v Ω_m).
    drive = Ci * amplifier
    i_from_v = control.feedback(armature * drive, motor.ki)    # I_a/V'_c at Ω_m = 0
    i_from_emf = -control.feedback(armature, drive * motor.ki)  # I_a/(k_v Ω_m) at V'_c = 0
    # Mechanical loop: Ω_m = R(s)(k_t I_a − C_r), closed through the back-emf path.
    loop = motor.kt * rotor * motor.kv * (-i_from_emf)
    velocity_input = control.minreal(i_from_v * motor.kt * rotor / (1 + loop), tol=1e-9, verbose=False)
    velocity_load = control.minreal(-rotor / (1 + loop), tol=1e-9, verbose=False)
    current_input = control.minreal(i_from_v / (1 + loop), tol=1e-9, verbose=False)
    current_load = control.minreal(i_from_emf * motor.kv * velocity_load, tol=1e-9, verbose=False)
    return ServomotorTransferFunctions(velocity_input, velocity_load, current_input, current_load)


def design_pi_current_loop(motor: DCServomotor, zeta: float, settling_time: float,
                           settling_factor: float = 4.6) -> tuple[PIRegulator, float]:
    """PI current regulator C_i(s) = K_I(1 + s T_I)/s giving I_a/V'_c a prescribed ζ and settling time.

    With Ω_m = 0 and T_v ≈ 0 the current loop is
    ``I_a/V'_c = (1 + s T_I)/(1 + s (R_a + k_i G_v K_I T_I)/(k_i G_v K_I) + s² L_a/(k_i G_v K_I))``
    (Problem 5.3); matching it with ``1 + 2ζ s/ω_n + s²/ω_n²`` and ``t_s = 4.6/(ζ ω_n)`` (1 %) gives
    ``K_I = L_a ω_n²/(k_i G_v)`` and ``T_I = 2ζ/ω_n − R_a/(k_i G_v K_I)``.

    Returns
    -------
    (regulator, omega_n)
    """
    zeta = as_positive(zeta, "zeta")
    settling_time = as_positive(settling_time, "settling_time")
    if motor.ki <= 0 or motor.La <= 0:
        raise ValueError("`motor` must have current feedback (ki > 0) and armature inductance La > 0")
    omega_n = settling_factor / (zeta * settling_time)
    gain = motor.ki * motor.Gv
    K_I = motor.La * omega_n**2 / gain
    T_I = 2 * zeta / omega_n - motor.Ra / (gain * K_I)
    if T_I <= 0:
        raise ValueError(f"settling time {settling_time} s is too slow for a PI with T_I > 0 "
                         f"(R_a/L_a = {motor.Ra / motor.La:g} 1/s already damps more)")
    return PIRegulator(K_I, T_I), omega_n


@dataclass(frozen=True)
class HydraulicMotor:
    """Hydraulic motor with servovalve and distributor (Sect. 5.1.2, Fig. S5.5), symbols of the book.

    ``kt`` torque/pressure, ``kx`` distributor, ``kr`` pressure feedback, ``kq`` flow/velocity,
    ``kc`` compressibility, ``kl`` leakage, ``Gs``, ``Ts`` servovalve gain and time constant,
    ``Im``, ``Fm`` motor inertia and viscous friction.
    """

    kt: float
    kx: float
    kr: float
    kq: float
    kc: float
    kl: float
    Gs: float
    Ts: float
    Im: float
    Fm: float

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            as_positive(value, name, allow_zero=name in ("kl", "Fm", "Ts"))


def hydraulic_transfer_functions(motor: HydraulicMotor
                                 ) -> tuple[control.TransferFunction, control.TransferFunction]:
    """(Θ_m/V_c, Θ_m/C_r) of the hydraulic drive by block reduction of Fig. S5.5 (Problem 5.4).

    Blocks: ``X = G_s/(1 + sT_s) V_c``; ``P = (1/(s k_c + k_l))((k_x/k_r)(X − P/k_x) − k_q Ω_m)``;
    ``C_m = k_t P``; ``Ω_m = (C_m − C_r)/(s I_m + F_m)``; ``Θ_m = Ω_m/s``.
    """
    m = motor
    s = control.tf("s")
    chamber = control.feedback(1 / (m.kc * s + m.kl), 1 / m.kr)    # P/(k_x X/k_r − k_q Ω_m)
    rotor = 1 / (m.Im * s + m.Fm)
    valve = m.Gs / (m.Ts * s + 1)
    omega_x = control.feedback(m.kt * chamber * rotor, m.kq) * (m.kx / m.kr)
    omega_load = -control.feedback(rotor, m.kt * chamber * m.kq)
    theta_v = control.minreal(valve * omega_x / s, tol=1e-9, verbose=False)
    theta_load = control.minreal(omega_load / s, tol=1e-9, verbose=False)
    return theta_v, theta_load


def frequency_samples(system: control.TransferFunction, omega: np.ndarray) -> np.ndarray:
    """G(jω) at the given frequencies [rad/s] (a complex array)."""
    omega = as_vector(omega, None, "omega")
    return np.asarray(system(1j * omega)).reshape(-1)
