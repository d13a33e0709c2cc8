#version 450
// Kelemen and Szirmay-Kalos visibility (2001), the cheap V of clear coats: 1 / (4 LoH^2).
float V_Kelemen(float LoH)
{
    return 0.25 / max(LoH * LoH, 1e-4);
}
