#version 450
// Rayleigh phase function of a sky shader: 3 / (16 pi) (1 + cos^2 theta).
const float PI = 3.14159265;

float rayleighPhase(float mu)
{
    return 3.0 / (16.0 * PI) * (1.0 + mu * mu);
}
