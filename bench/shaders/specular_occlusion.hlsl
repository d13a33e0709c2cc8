// Specular occlusion from ambient occlusion (Lagarde and de Rousiers 2014, "Moving Frostbite to
// PBR", listing 26).
float ComputeSpecOcclusion(float NdotV, float AO, float roughness)
{
    return saturate(pow(NdotV + AO, exp2(-16.0 * roughness - 1.0)) - 1.0 + AO);
}
