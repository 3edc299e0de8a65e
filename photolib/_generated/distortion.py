# generated from photolib/derive/distortion.py, do not edit
# source sha256: 59470d5e774314e23a3337ee9a6db610699114c3c23695a69c5f51565a0ab402
# hashed: derive/distortion.py, derive/_spec.py
# regenerate with: python -m photolib codegen   (SymPy 1.14)
"""NumPy code generated from :mod:`photolib.derive.distortion`."""

import numpy as np

__all__ = ['distortion_delta', 'distortion_delta_and_jacobian', 'distortion_jacobian_params']


def distortion_delta(x, y, A1, A2, A3, r0, B1, B2, C1, C2):
    """Δx', Δy' (image unit) at the reduced measured coordinates x, y (image unit).

    Returns (dx, dy); all arguments broadcast like NumPy arrays.
    """
    _t0 = 2*x*y
    _t1 = (y*y)
    _t2 = (x*x)
    _t3 = _t1 + _t2
    _t4 = A1*_t3 - A1*(r0*r0) + A2*(_t3*_t3) - A2*(r0*r0*r0*r0) + A3*(_t3*_t3*_t3) - A3*r0**6
    dx = B1*(_t1 + 3*_t2) + B2*_t0 + C1*x + C2*y + _t4*x
    dy = B1*_t0 + B2*(3*_t1 + _t2) + _t4*y
    return dx, dy


def distortion_delta_and_jacobian(x, y, A1, A2, A3, r0, B1, B2, C1, C2):
    """Δx', Δy' and their derivatives with respect to x and y (dimensionless), for Newton's
    iteration; r² = x² + y², q(r²) and q'(r²) in Horner form.

    Returns (dx, dy, ddx_dx, ddx_dy, ddy_dx, ddy_dy); all arguments broadcast like NumPy arrays.
    """
    _r2 = (x*x) + (y*y)
    _q = -A1*(r0*r0) - A2*(r0*r0*r0*r0) - A3*r0**6 + _r2*(A1 + _r2*(A2 + A3*_r2))
    _dq = A1 + _r2*(2*A2 + 3*A3*_r2)
    _t0 = (y*y)
    _t1 = 2*y
    _t2 = B2*_t1
    _t3 = (x*x)
    _t4 = B1*x
    _t5 = 2*_dq
    _t6 = B1*_t1 + 2*B2*x + _dq*_t1*x
    dx = B1*_t0 + 3*B1*_t3 + C1*x + C2*y + _q*x + _t2*x
    dy = 3*B2*_t0 + B2*_t3 + _q*y + _t1*_t4
    ddx_dx = C1 + _q + _t2 + _t3*_t5 + 6*_t4
    ddx_dy = C2 + _t6
    ddy_dx = _t6
    ddy_dy = 6*B2*y + _q + _t0*_t5 + 2*_t4
    return dx, dy, ddx_dx, ddx_dy, ddy_dx, ddy_dy


def distortion_jacobian_params(x, y, A1, A2, A3, r0, B1, B2, C1, C2):
    """∂Δx'/∂p, ∂Δy'/∂p for p in (A1, A2, A3, B1, B2, C1, C2), for self-calibration.

    Returns (dx_dA1, dy_dA1, dx_dA2, dy_dA2, dx_dA3, dy_dA3, dx_dB1, dy_dB1, dx_dB2, dy_dB2, dx_dC1, dy_dC1, dx_dC2, dy_dC2); all arguments broadcast like NumPy arrays.
    """
    _t0 = (x*x)
    _t1 = (y*y)
    _t2 = _t0 + _t1
    _t3 = _t2 - (r0*r0)
    _t4 = (_t2*_t2) - (r0*r0*r0*r0)
    _t5 = (_t2*_t2*_t2) - r0**6
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
