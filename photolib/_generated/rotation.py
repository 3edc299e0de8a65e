# generated from photolib/derive/rotation.py, do not edit
# source sha256: 897d51f97d7204ba382ee674513d85e1a5167ea53cfb122106059ad253ba4ba7
# hashed: derive/rotation.py, derive/_spec.py
# regenerate with: python -m photolib codegen   (SymPy 1.14)
"""NumPy code generated from :mod:`photolib.derive.rotation`."""

import numpy as np

__all__ = ['rotation_opk_elements', 'rotation_pok_elements']


def rotation_opk_elements(omega, phi, kappa):
    """Elements r11..r33 (row-major) of R = R_ω·R_φ·R_κ; angles in radians.

    Returns (r11, r12, r13, r21, r22, r23, r31, r32, r33); all arguments broadcast like NumPy arrays.
    """
    _t0 = np.cos(kappa)
    _t1 = np.cos(phi)
    _t2 = np.sin(kappa)
    _t3 = np.sin(phi)
    _t4 = np.cos(omega)
    _t5 = _t2*_t4
    _t6 = np.sin(omega)
    _t7 = _t0*_t6
    _t8 = _t2*_t6
    r11 = _t0*_t1
    r12 = -_t1*_t2
    r13 = _t3
    r21 = _t3*_t7 + _t5
    r22 = _t0*_t4 - _t3*_t8
    r23 = -_t1*_t6
    r31 = -_t0*_t3*_t4 + _t8
    r32 = _t3*_t5 + _t7
    r33 = _t1*_t4
    return r11, r12, r13, r21, r22, r23, r31, r32, r33


def rotation_pok_elements(omega, phi, kappa):
    """Elements r11..r33 (row-major) of R = R_φ·R_ω·R_κ; angles in radians.

    Returns (r11, r12, r13, r21, r22, r23, r31, r32, r33); all arguments broadcast like NumPy arrays.
    """
    _t0 = np.cos(kappa)
    _t1 = np.cos(phi)
    _t2 = _t0*_t1
    _t3 = np.sin(omega)
    _t4 = np.sin(kappa)
    _t5 = np.sin(phi)
    _t6 = _t4*_t5
    _t7 = _t1*_t4
    _t8 = np.cos(omega)
    r11 = _t2 + _t3*_t6
    r12 = _t0*_t3*_t5 - _t7
    r13 = _t5*_t8
    r21 = _t4*_t8
    r22 = _t0*_t8
    r23 = -_t3
    r31 = -_t0*_t5 + _t3*_t7
    r32 = _t2*_t3 + _t6
    r33 = _t1*_t8
    return r11, r12, r13, r21, r22, r23, r31, r32, r33
