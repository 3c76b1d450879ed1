# SPDX-License-Identifier: GPL-3.0-or-later
"""Butcher tableaus of the explicit Runge-Kutta maps, typed here from the published sources
(not from the C library's files, which tests/test_rk_order_conditions.py compares with these):

  rk4  the classical Runge-Kutta method (Kutta 1901; Hairer, Norsett, Wanner, Solving Ordinary
       Differential Equations I, 2nd ed., Springer 1993, Sect. II.1), exact fractions
  rk8  the eighth-order solution of DOP853: the constants C2..C11, A21..A1211, B1..B12 of the
       subroutine DP86CO in E. Hairer and G. Wanner's dop853.f (version of April 25, 1996,
       corrected March 4, 2002), the code of the same book; the 30-digit decimals as printed,
       so that in multiple precision they are the published method, in float64 the nearest
       doubles (what a C compiler makes of the same digits)

tableau(name, a) gives (A, b, c) in the arithmetic a: A as s lists of s numbers (zero on and
above the diagonal), b and c as lists.
"""

from __future__ import annotations

from .arith import Arith, Matrix, Vector

# DP86CO's A: stage i's row as {j: digits}, stages and columns numbered from 1 as in the code;
# every entry not listed is zero
DOP853_A = {
    2: {1: "5.26001519587677318785587544488e-2"},
    3: {1: "1.97250569845378994544595329183e-2", 2: "5.91751709536136983633785987549e-2"},
    4: {1: "2.95875854768068491816892993775e-2", 3: "8.87627564304205475450678981324e-2"},
    5: {
        1: "2.41365134159266685502369798665e-1",
        3: "-8.84549479328286085344864962717e-1",
        4: "9.24834003261792003115737966543e-1",
    },
    6: {
        1: "3.7037037037037037037037037037e-2",
        4: "1.70828608729473871279604482173e-1",
        5: "1.25467687566822425016691814123e-1",
    },
    7: {
        1: "3.7109375e-2",
        4: "1.70252211019544039314978060272e-1",
        5: "6.02165389804559606850219397283e-2",
        6: "-1.7578125e-2",
    },
    8: {
        1: "3.70920001185047927108779319836e-2",
        4: "1.70383925712239993810214054705e-1",
        5: "1.07262030446373284651809199168e-1",
        6: "-1.53194377486244017527936158236e-2",
        7: "8.27378916381402288758473766002e-3",
    },
    9: {
        1: "6.24110958716075717114429577812e-1",
        4: "-3.36089262944694129406857109825e0",
        5: "-8.68219346841726006818189891453e-1",
        6: "2.75920996994467083049415600797e1",
        7: "2.01540675504778934086186788979e1",
        8: "-4.34898841810699588477366255144e1",
    },
    10: {
        1: "4.77662536438264365890433908527e-1",
        4: "-2.48811461997166764192642586468e0",
        5: "-5.90290826836842996371446475743e-1",
        6: "2.12300514481811942347288949897e1",
        7: "1.52792336328824235832596922938e1",
        8: "-3.32882109689848629194453265587e1",
        9: "-2.03312017085086261358222928593e-2",
    },
    11: {
        1: "-9.3714243008598732571704021658e-1",
        4: "5.18637242884406370830023853209e0",
        5: "1.09143734899672957818500254654e0",
        6: "-8.14978701074692612513997267357e0",
        7: "-1.85200656599969598641566180701e1",
        8: "2.27394870993505042818970056734e1",
        9: "2.49360555267965238987089396762e0",
        10: "-3.0467644718982195003823669022e0",
    },
    12: {
        1: "2.27331014751653820792359768449e0",
        4: "-1.05344954667372501984066689879e1",
        5: "-2.00087205822486249909675718444e0",
        6: "-1.79589318631187989172765950534e1",
        7: "2.79488845294199600508499808837e1",
        8: "-2.85899827713502369474065508674e0",
        9: "-8.87285693353062954433549289258e0",
        10: "1.23605671757943030647266201528e1",
        11: "6.43392746015763530355970484046e-1",
    },
}
DOP853_B = {
    1: "5.42937341165687622380535766363e-2",
    6: "4.45031289275240888144113950566e0",
    7: "1.89151789931450038304281599044e0",
    8: "-5.8012039600105847814672114227e0",
    9: "3.1116436695781989440891606237e-1",
    10: "-1.52160949662516078556178806805e-1",
    11: "2.01365400804030348374776537501e-1",
    12: "4.47106157277725905176885569043e-2",
}
# c1 = 0; c12 = 1 (the code evaluates its twelfth stage at X + H)
DOP853_C = {
    2: "0.526001519587677318785587544488e-1",
    3: "0.789002279381515978178381316732e-1",
    4: "0.118350341907227396726757197510e0",
    5: "0.281649658092772603273242802490e0",
    6: "0.333333333333333333333333333333e0",
    7: "0.25e0",
    8: "0.307692307692307692307692307692e0",
    9: "0.651282051282051282051282051282e0",
    10: "0.6e0",
    11: "0.857142857142857142857142857142e0",
    12: "1",
}

ORDER = {"rk4": 4, "rk8": 8}


def _rk4(a: Arith) -> tuple[Matrix, Vector, Vector]:
    half, one, zero = a.num(1) / 2, a.num(1), a.num(0)
    A = [[zero] * 4 for _ in range(4)]
    A[1][0], A[2][1], A[3][2] = half, half, one
    b = [one / 6, one / 3, one / 3, one / 6]
    c = [zero, half, half, one]
    return A, b, c


def _dop853(a: Arith) -> tuple[Matrix, Vector, Vector]:
    s, zero = 12, a.num(0)
    A = [[zero] * s for _ in range(s)]
    for i, row in DOP853_A.items():
        for j, digits in row.items():
            A[i - 1][j - 1] = a.num(digits)
    b = [a.num(DOP853_B[i]) if i in DOP853_B else zero for i in range(1, s + 1)]
    c = [a.num(DOP853_C[i]) if i in DOP853_C else zero for i in range(1, s + 1)]
    return A, b, c


def tableau(name: str, a: Arith) -> tuple[Matrix, Vector, Vector]:
    if name == "rk4":
        return _rk4(a)
    if name == "rk8":
        return _dop853(a)
    raise ValueError("no Runge-Kutta tableau named %r" % (name,))
