#version 450
// Height-correlated Smith visibility for GGX, V = G2 / (4 NoL NoV)
// (Heitz 2014, in the form of Lagarde and de Rousiers 2014).
float V_SmithGGXCorrelated(float NoV, float NoL, float roughness)
{
    float a = roughness * roughness;
    float a2 = a * a;
    float lambdaV = NoL * sqrt(NoV * NoV * (1.0 - a2) + a2);
    float lambdaL = NoV * sqrt(NoL * NoL * (1.0 - a2) + a2);
    return 0.5 / max(lambdaV + lambdaL, 1e-5);
}
