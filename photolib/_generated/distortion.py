# generated from photolib/derive/distortion.py, do not edit
# source sha256: 0f3e49f454849d800e2a9c30103cbe429b29556acaf5d458187442d894a4adbf
# regenerate with: python -m photolib codegen   (SymPy 1.14)
"""NumPy code generated from :mod:`photolib.derive.distortion`."""

import numpy as np

__all__ = ['distortion_delta', 'distortion_delta_and_jacobian', 'distortion_jacobian_params']


def distortion_delta(x, y, A1, A2, A3, r0, B1, B2, C1, C2):
    """Δx', Δy' (image unit) at the reduced measured coordinates x, y (image unit).

    Returns (dx, dy); all arguments broadcast like NumPy arrays.
    """
    _t0 = 2*x*y
    _t1 = y**2
    _t2 = x**2
    _t3 = _t1 + _t2
    _t4 = A1*_t3 - A1*r0**2 + A2*_t3**2 - A2*r0**4 + A3*_t3**3 - A3*r0**6
    dx = B1*(_t1 + 3*_t2) + B2*_t0 + C1*x + C2*y + _t4*x
    dy = B1*_t0 + B2*(3*_t1 + _t2) + _t4*y
    return dx, dy


def distortion_delta_and_jacobian(x, y, A1, A2, A3, r0, B1, B2, C1, C2):
    """Δx', Δy' and their derivatives with respect to x and y (dimensionless), for Newton's
    iteration.

    Returns (dx, dy, ddx_dx, ddx_dy, ddy_dx, ddy_dy); all arguments broadcast like NumPy arrays.
    """
    _t0 = 2*y
    _t1 = B2*_t0
    _t2 = y**2
    _t3 = x**2
    _t4 = A1*r0**2
    _t5 = A2*r0**4
    _t6 = A3*r0**6
    _t7 = _t2 + _t3
    _t8 = _t7**2
    _t9 = _t7**3
    _t10 = A1*_t7 + A2*_t8 + A3*_t9 - _t4 - _t5 - _t6
    _t11 = B1*x
    _t12 = 2*A1
    _t13 = 4*A2*_t7
    _t14 = A3*_t8
    _t15 = _t12*x + _t13*x + 6*_t14*x
    _t16 = A1*_t7 + A2*_t8 + A3*_t9 - _t4 - _t5 - _t6
    _t17 = 6*y
    _t18 = _t12*y + _t13*y + _t14*_t17
    _t19 = B1*_t0 + 2*B2*x
    dx = B1*(_t2 + 3*_t3) + C1*x + C2*y + _t1*x + _t10*x
    dy = B2*(3*_t2 + _t3) + _t0*_t11 + _t10*y
    ddx_dx = C1 + _t1 + 6*_t11 + _t15*x + _t16
    ddx_dy = C2 + _t18*x + _t19
    ddy_dx = _t15*y + _t19
    ddy_dy = B2*_t17 + 2*_t11 + _t16 + _t18*y
    return dx, dy, ddx_dx, ddx_dy, ddy_dx, ddy_dy


def distortion_jacobian_params(x, y, A1, A2, A3, r0, B1, B2, C1, C2):
    """∂Δx'/∂p, ∂Δy'/∂p for p in (A1, A2, A3, B1, B2, C1, C2), for self-calibration.

    Returns (dx_dA1, dy_dA1, dx_dA2, dy_dA2, dx_dA3, dy_dA3, dx_dB1, dy_dB1, dx_dB2, dy_dB2, dx_dC1, dy_dC1, dx_dC2, dy_dC2); all arguments broadcast like NumPy arrays.
    """
    _t0 = x**2
    _t1 = y**2
    _t2 = _t0 + _t1
    _t3 = _t2 - r0**2
    _t4 = _t2**2 - r0**4
    _t5 = _t2**3 - r0**6
    _t6 = 2*x*y
    dx_dA1 = _t3*x
    dy_dA1 = _t3*y
    dx_dA2 = _t4*x
    dy_dA2 = _t4*y
    dx_dA3 = _t5*x
    dy_dA3 = _t5*y
    dx_dB1 = 3*_t0 + _t1
    dy_dB1 = _t6
    dx_dB2 = _t6
    dy_dB2 = _t0 + 3*_t1
    dx_dC1 = x
    dy_dC1 = np.zeros(np.broadcast(x, y, A1, A2, A3, r0, B1, B2, C1, C2).shape) + 0
    dx_dC2 = y
    dy_dC2 = np.zeros(np.broadcast(x, y, A1, A2, A3, r0, B1, B2, C1, C2).shape) + 0
    return dx_dA1, dy_dA1, dx_dA2, dy_dA2, dx_dA3, dy_dA3, dx_dB1, dy_dB1, dx_dB2, dy_dB2, dx_dC1, dy_dC1, dx_dC2, dy_dC2
