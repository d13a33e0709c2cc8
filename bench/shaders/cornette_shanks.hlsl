// Cornette-Shanks phase function (Cornette and Shanks 1992), the Mie phase of many
// atmosphere shaders: HG with a (1 + cos^2) Rayleigh-like factor and its normalisation.
static const float kPi = 3.14159265f;

float PhaseCornetteShanks(float cosTheta, float g)
{
    const float g2 = g * g;
    float num = 3.0f * (1.0f - g2) * (1.0f + cosTheta * cosTheta);
    float den = 8.0f * kPi * (2.0f + g2) * pow(max(1.0f + g2 - 2.0f * g * cosTheta, 1e-4f), 1.5f);
    return num / den;
}
