// SMPTE ST 2084 (PQ) EOTF: a code value in [0, 1] to luminance, normalised to 10000 cd/m^2.
static const float PQ_m1 = 0.1593017578125;   // 2610 / 16384
static const float PQ_m2 = 78.84375;          // 2523 / 4096 * 128
static const float PQ_c1 = 0.8359375;         // 3424 / 4096
static const float PQ_c2 = 18.8515625;        // 2413 / 4096 * 32
static const float PQ_c3 = 18.6875;           // 2392 / 4096 * 32

float PQ_EOTF(float N)
{
    float Np = pow(saturate(N), 1.0 / PQ_m2);
    float L = max(Np - PQ_c1, 0.0) / (PQ_c2 - PQ_c3 * Np);
    return pow(L, 1.0 / PQ_m1);
}
