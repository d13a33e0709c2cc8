#version 450
// Neubelt and Pettineo's cloth visibility (SIGGRAPH 2013 course, The Order: 1886),
// clamped to 1 as engines do.
float V_Neubelt(float NoV, float NoL)
{
    float d = 4.0 * (NoL + NoV - NoL * NoV);
    return clamp(1.0 / max(d, 1e-4), 0.0, 1.0);
}
