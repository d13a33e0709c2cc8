#version 450
// Schlick's approximation of the Henyey-Greenstein phase function (Blasi, Le Saec and
// Schlick 1993): a rational function with the same shape, k fitted from g.
#define PI 3.14159265358979

float schlickK(float g)
{
    // k = 1.55 g - 0.55 g^3 matches the anisotropy of HG's lobe
    return g * (1.55 - 0.55 * g * g);
}

float phaseSchlick(float cosTheta, float g)
{
    float k = schlickK(g);
    float t = 1.0 - k * cosTheta;
    return (1.0 - k * k) / (4.0 * PI * t * t);
}
