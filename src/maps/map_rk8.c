/* SPDX-License-Identifier: GPL-3.0-or-later */
/* An explicit Runge-Kutta method of order 8 as a map: the eighth-order solution of Dormand and
 * Prince's 8(5,3) pair as coded in Hairer and Wanner's DOP853, 12 stages (the error estimators
 * and the dense output's extra stages are not used: the step is fixed). phi_T(mu) =
 * sum_i b_i k_i, k_i = q0(t + c_i T, mu + T sum_{j<i} a_ij k_j): explicit (phi does not depend
 * on mu+), 12 evaluations of q0, no Newton; on the manifold a step is the method's step on
 * mu' = q0(t, mu). Its error constants are small: on x'' = -x^3 from (1, 0) over [0, 2] an
 * error of 4e-11 takes it 120 evaluations of q0 (T = 0.2), rk4 640 (T = 0.0125). Its stability
 * polynomial keeps |R(z)| <= 1 on the imaginary axis up to |z| = 5.96, on the negative real
 * axis up to 6.39.
 *
 * The coefficients are those of the subroutine DP86CO in dop853.f (E. Hairer and G. Wanner,
 * version of April 25, 1996, small corrections March 4, 2002), the code of Hairer, Norsett,
 * Wanner, Solving Ordinary Differential Equations I, 2nd ed., Springer 1993; the names in the
 * comments are that file's (a121 is a_{12,1}, a1211 is a_{12,11}). Only the digits a double
 * holds are used; the order conditions up to 8 hold for these doubles to their rounding
 * (tools/stabdae_ref/tests/test_rk_order_conditions.py). */
#include "map_rk.h"

/* DP86CO: a21 .. a1211 (stages 2-12, the zeros of the sparse tableau written out) */
static const double rk8_a[] = {5.26001519587677318785587544488e-2,  /* a21 */
                               1.97250569845378994544595329183e-2,  /* a31 */
                               5.91751709536136983633785987549e-2,  /* a32 */
                               2.95875854768068491816892993775e-2,  /* a41 */
                               0.0,                                 /* a42 */
                               8.87627564304205475450678981324e-2,  /* a43 */
                               2.41365134159266685502369798665e-1,  /* a51 */
                               0.0,                                 /* a52 */
                               -8.84549479328286085344864962717e-1, /* a53 */
                               9.24834003261792003115737966543e-1,  /* a54 */
                               3.7037037037037037037037037037e-2,   /* a61 */
                               0.0,                                 /* a62 */
                               0.0,                                 /* a63 */
                               1.70828608729473871279604482173e-1,  /* a64 */
                               1.25467687566822425016691814123e-1,  /* a65 */
                               3.7109375e-2,                        /* a71 */
                               0.0,                                 /* a72 */
                               0.0,                                 /* a73 */
                               1.70252211019544039314978060272e-1,  /* a74 */
                               6.02165389804559606850219397283e-2,  /* a75 */
                               -1.7578125e-2,                       /* a76 */
                               3.70920001185047927108779319836e-2,  /* a81 */
                               0.0,                                 /* a82 */
                               0.0,                                 /* a83 */
                               1.70383925712239993810214054705e-1,  /* a84 */
                               1.07262030446373284651809199168e-1,  /* a85 */
                               -1.53194377486244017527936158236e-2, /* a86 */
                               8.27378916381402288758473766002e-3,  /* a87 */
                               6.24110958716075717114429577812e-1,  /* a91 */
                               0.0,                                 /* a92 */
                               0.0,                                 /* a93 */
                               -3.36089262944694129406857109825e0,  /* a94 */
                               -8.68219346841726006818189891453e-1, /* a95 */
                               2.75920996994467083049415600797e1,   /* a96 */
                               2.01540675504778934086186788979e1,   /* a97 */
                               -4.34898841810699588477366255144e1,  /* a98 */
                               4.77662536438264365890433908527e-1,  /* a101 */
                               0.0,                                 /* a102 */
                               0.0,                                 /* a103 */
                               -2.48811461997166764192642586468e0,  /* a104 */
                               -5.90290826836842996371446475743e-1, /* a105 */
                               2.12300514481811942347288949897e1,   /* a106 */
                               1.52792336328824235832596922938e1,   /* a107 */
                               -3.32882109689848629194453265587e1,  /* a108 */
                               -2.03312017085086261358222928593e-2, /* a109 */
                               -9.3714243008598732571704021658e-1,  /* a111 */
                               0.0,                                 /* a112 */
                               0.0,                                 /* a113 */
                               5.18637242884406370830023853209e0,   /* a114 */
                               1.09143734899672957818500254654e0,   /* a115 */
                               -8.14978701074692612513997267357e0,  /* a116 */
                               -1.85200656599969598641566180701e1,  /* a117 */
                               2.27394870993505042818970056734e1,   /* a118 */
                               2.49360555267965238987089396762e0,   /* a119 */
                               -3.0467644718982195003823669022e0,   /* a1110 */
                               2.27331014751653820792359768449e0,   /* a121 */
                               0.0,                                 /* a122 */
                               0.0,                                 /* a123 */
                               -1.05344954667372501984066689879e1,  /* a124 */
                               -2.00087205822486249909675718444e0,  /* a125 */
                               -1.79589318631187989172765950534e1,  /* a126 */
                               2.79488845294199600508499808837e1,   /* a127 */
                               -2.85899827713502369474065508674e0,  /* a128 */
                               -8.87285693353062954433549289258e0,  /* a129 */
                               1.23605671757943030647266201528e1,   /* a1210 */
                               6.43392746015763530355970484046e-1}; /* a1211 */

/* DP86CO: b1 .. b12, the weights of the eighth-order solution (b2 .. b5 are 0) */
static const double rk8_b[] = {5.42937341165687622380535766363e-2,  /* b1 */
                               0.0,                                 /* b2 */
                               0.0,                                 /* b3 */
                               0.0,                                 /* b4 */
                               0.0,                                 /* b5 */
                               4.45031289275240888144113950566e0,   /* b6 */
                               1.89151789931450038304281599044e0,   /* b7 */
                               -5.8012039600105847814672114227e0,   /* b8 */
                               3.1116436695781989440891606237e-1,   /* b9 */
                               -1.52160949662516078556178806805e-1, /* b10 */
                               2.01365400804030348374776537501e-1,  /* b11 */
                               4.47106157277725905176885569043e-2}; /* b12 */

/* DP86CO: c2 .. c11; c1 = 0 and c12 = 1 (its twelfth stage is at X + H) */
static const double rk8_c[] = {0.0,                                 /* c1 */
                               0.526001519587677318785587544488e-1, /* c2 */
                               0.789002279381515978178381316732e-1, /* c3 */
                               0.118350341907227396726757197510e0,  /* c4 */
                               0.281649658092772603273242802490e0,  /* c5 */
                               0.333333333333333333333333333333e0,  /* c6 */
                               0.25e0,                              /* c7 */
                               0.307692307692307692307692307692e0,  /* c8 */
                               0.651282051282051282051282051282e0,  /* c9 */
                               0.6e0,                               /* c10 */
                               0.857142857142857142857142857142e0,  /* c11 */
                               1.0};                                /* c12 */

static const sdae_rk_tableau rk8 = {12, rk8_a, rk8_b, rk8_c};

static size_t rk8_scratch(const sdae_model *m, const sdae_options *o) {
  (void)o;
  return sdae__rk_scratch(&rk8, m);
}

static int rk8_phi(sdae_map_ctx *c, double t, double T, const double *mu, const double *mu_next,
                   double *out) {
  (void)mu_next;
  return sdae__rk_phi(&rk8, c, t, T, mu, out);
}

static const sdae_map_type rk8_type = {
    .name = "rk8",
    .order = 8,
    .implicit = 0,
    .scratch = rk8_scratch,
    .phi = rk8_phi,
};

const sdae_map_type *const sdae_map_rk8 = &rk8_type;
