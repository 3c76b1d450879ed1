"""The chain example's random start: the Mersenne Twister MT19937 (Matsumoto and Nishimura,
1998, with their 2002 seeding init_genrand) and uniform numbers in [a, b), written from the
generator's definition. GSL's gsl_rng_mt19937 is this generator (GSL seeds 0 as 4357), its
gsl_rng_uniform is the 32-bit output divided by 2^32 and gsl_ran_flat(a, b) is
a (1 - u) + b u, so the C program `chain --seed S` and chain_x0(N, S) start from the same
state.
"""

N_STATE, M_SHIFT = 624, 397
MASK32, UPPER, LOWER = 0xFFFFFFFF, 0x80000000, 0x7FFFFFFF
MATRIX_A = 0x9908B0DF


class MT19937:
    """next32() gives the generator's 32-bit outputs in order."""

    def __init__(self, seed):
        s = seed & MASK32
        if s == 0:
            s = 4357  # GSL's choice for seed 0
        self.mt = [s]
        for i in range(1, N_STATE):
            prev = self.mt[-1]
            self.mt.append((1812433253 * (prev ^ (prev >> 30)) + i) & MASK32)
        self.index = N_STATE

    def twist(self):
        mt = self.mt
        for k in range(N_STATE):
            y = (mt[k] & UPPER) | (mt[(k + 1) % N_STATE] & LOWER)
            mt[k] = mt[(k + M_SHIFT) % N_STATE] ^ (y >> 1) ^ (MATRIX_A if y & 1 else 0)
        self.index = 0

    def next32(self):
        if self.index >= N_STATE:
            self.twist()
        y = self.mt[self.index]
        self.index += 1
        y ^= y >> 11  # tempering
        y ^= (y << 7) & 0x9D2C5680
        y ^= (y << 15) & 0xEFC60000
        y ^= y >> 18
        return y

    def uniform(self):
        """u in [0, 1): the output over 2^32 (exact in a double)."""
        return self.next32() / 4294967296.0

    def flat(self, a, b):
        """A number in [a, b) from one output, a (1 - u) + b u."""
        u = self.uniform()
        return a * (1 - u) + b * u


def chain_x0(N, seed):
    """The chain's start (X, Y, Xdot, Ydot per mass, 4 N doubles): X_i in [-0.5, 0.5),
    Y_i in [-0.2, 0.2), Xdot_i and Ydot_i in [-0.1, 0.1), drawn mass by mass in that order."""
    if int(seed) != seed or seed < 0:
        raise ValueError("seed must be a whole number >= 0, got %r" % (seed,))
    r = MT19937(int(seed))
    x = []
    for _ in range(int(N)):
        x += [r.flat(-0.5, 0.5), r.flat(-0.2, 0.2), r.flat(-0.1, 0.1), r.flat(-0.1, 0.1)]
    return x
