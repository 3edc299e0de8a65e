# generated from photolib/derive/collinearity.py, do not edit
# source sha256: 58995f6f71453b8d647c01e5afafcf295ea17f26e62a379d0236c7998ee706eb
# hashed: derive/collinearity.py, derive/_spec.py, derive/rotation.py
# regenerate with: python -m photolib codegen   (SymPy 1.14)
"""NumPy code generated from :mod:`photolib.derive.collinearity`."""

import numpy as np

__all__ = ['collinearity_jacobian_interior', 'collinearity_jacobian_opk', 'project_r']


def project_r(X, Y, Z, X0, Y0, Z0, r11, r12, r13, r21, r22, r23, r31, r32, r33, c, x0, y0):
    """Ideal image coordinates x', y' (image unit, e.g. mm) and the depth N = r13·ΔX +
    r23·ΔY + r33·ΔZ (object unit; N < 0 in front) for a general R given by its elements
    r11..r33.

    Returns (x, y, N); all arguments broadcast like NumPy arrays.
    """
    _t0 = X - X0
    _t1 = Y - Y0
    _t2 = Z - Z0
    _t3 = _t0*r13 + _t1*r23 + _t2*r33
    _t4 = c/_t3
    x = -_t4*(_t0*r11 + _t1*r21 + _t2*r31) + x0
    y = -_t4*(_t0*r12 + _t1*r22 + _t2*r32) + y0
    N = _t3
    return x, y, N


def collinearity_jacobian_opk(X, Y, Z, X0, Y0, Z0, omega, phi, kappa, c):
    """∂x'/∂p and ∂y'/∂p for p in (X0, Y0, Z0, ω, φ, κ, X, Y, Z), R = R_ω·R_φ·R_κ; image
    unit per object unit for lengths, image unit per radian for angles.

    Returns (dx_dX0, dy_dX0, dx_dY0, dy_dY0, dx_dZ0, dy_dZ0, dx_domega, dy_domega, dx_dphi, dy_dphi, dx_dkappa, dy_dkappa, dx_dX, dy_dX, dx_dY, dy_dY, dx_dZ, dy_dZ); all arguments broadcast like NumPy arrays.
    """
    _t0 = np.cos(kappa)
    _t1 = np.cos(phi)
    _t2 = np.sin(phi)
    _t3 = X - X0
    _t4 = _t2*_t3
    _t5 = Z - Z0
    _t6 = np.cos(omega)
    _t7 = _t1*_t6
    _t8 = Y - Y0
    _t9 = np.sin(omega)
    _t10 = _t1*_t9
    _t11 = -_t10*_t8 + _t4 + _t5*_t7
    _t12 = c/_t11
    _t13 = _t1*_t12
    _t14 = _t1*_t3
    _t15 = _t0*_t14
    _t16 = np.sin(kappa)
    _t17 = _t16*_t6
    _t18 = _t0*_t9
    _t19 = _t17 + _t18*_t2
    _t20 = _t16*_t9
    _t21 = _t0*_t6
    _t22 = -_t2*_t21 + _t20
    _t23 = _t15 + _t19*_t8 + _t22*_t5
    _t24 = c/(_t11*_t11)
    _t25 = _t2*_t24
    _t26 = _t0*_t13 - _t23*_t25
    _t27 = _t17*_t2 + _t18
    _t28 = -_t0*_t6 + _t2*_t20
    _t29 = -_t28
    _t30 = -_t14*_t16 + _t27*_t5 + _t29*_t8
    _t31 = _t13*_t16 + _t25*_t30
    _t32 = -_t19
    _t33 = _t10*_t24
    _t34 = _t23*_t33
    _t35 = _t30*_t33
    _t36 = -_t22
    _t37 = _t24*_t7
    _t38 = _t23*_t37
    _t39 = -_t27
    _t40 = _t30*_t37
    _t41 = _t24*(_t10*_t5 + _t7*_t8)
    _t42 = _t1*_t5
    _t43 = _t24*(-_t14 + _t2*_t5*_t6 - _t2*_t8*_t9)
    dx_dX0 = _t26
    dy_dX0 = -_t31
    dx_dY0 = -_t12*_t32 + _t34
    dy_dY0 = -_t12*_t28 + _t35
    dx_dZ0 = -_t12*_t36 - _t38
    dy_dZ0 = -_t12*_t39 - _t40
    dx_domega = -_t12*(_t19*_t5 + _t36*_t8) - _t23*_t41
    dy_domega = -_t12*(_t29*_t5 + _t39*_t8) - _t30*_t41
    dx_dphi = -_t12*(_t0*_t1*_t8*_t9 - _t0*_t4 - _t21*_t42) - _t23*_t43
    dy_dphi = -_t12*(-_t1*_t20*_t8 + _t16*_t4 + _t17*_t42) - _t30*_t43
    dx_dkappa = -_t12*_t30
    dy_dkappa = -_t12*(-_t15 + _t32*_t8 + _t36*_t5)
    dx_dX = -_t26
    dy_dX = _t31
    dx_dY = -_t12*_t19 - _t34
    dy_dY = -_t12*_t29 - _t35
    dx_dZ = -_t12*_t22 + _t38
    dy_dZ = -_t12*_t27 + _t40
    return dx_dX0, dy_dX0, dx_dY0, dy_dY0, dx_dZ0, dy_dZ0, dx_domega, dy_domega, dx_dphi, dy_dphi, dx_dkappa, dy_dkappa, dx_dX, dy_dX, dx_dY, dy_dY, dx_dZ, dy_dZ


def collinearity_jacobian_interior(X, Y, Z, X0, Y0, Z0, r11, r12, r13, r21, r22, r23, r31, r32, r33, c):
    """∂x'/∂q and ∂y'/∂q for the interior orientation q in (c, x'0, y'0) of the ideal model
    x' = x'0 − c·kx/N, y' = y'0 − c·ky/N, for a general R given by its elements r11..r33
    (dimensionless): the bundle adjustment's self-calibration columns before the
    distortion's share.

    Returns (dx_dc, dy_dc, dx_dx0, dy_dx0, dx_dy0, dy_dy0); all arguments broadcast like NumPy arrays.
    """
    _t0 = X - X0
    _t1 = Y - Y0
    _t2 = Z - Z0
    _t3 = (_t0*r13 + _t1*r23 + _t2*r33)**(-1.0)
    dx_dc = -_t3*(_t0*r11 + _t1*r21 + _t2*r31)
    dy_dc = -_t3*(_t0*r12 + _t1*r22 + _t2*r32)
    dx_dx0 = np.zeros(np.broadcast(X, Y, Z, X0, Y0, Z0, r11, r12, r13, r21, r22, r23, r31, r32, r33, c).shape) + 1
    dy_dx0 = np.zeros(np.broadcast(X, Y, Z, X0, Y0, Z0, r11, r12, r13, r21, r22, r23, r31, r32, r33, c).shape) + 0
    dx_dy0 = np.zeros(np.broadcast(X, Y, Z, X0, Y0, Z0, r11, r12, r13, r21, r22, r23, r31, r32, r33, c).shape) + 0
    dy_dy0 = np.zeros(np.broadcast(X, Y, Z, X0, Y0, Z0, r11, r12, r13, r21, r22, r23, r31, r32, r33, c).shape) + 1
    return dx_dc, dy_dc, dx_dx0, dy_dx0, dx_dy0, dy_dy0
