#version 450
// Smooth spot light cone: 0 outside the outer cone, 1 inside the inner one, a smoothstep between.
float spotCone(float cosAngle, float cosOuter, float penumbra)
{
    float cosInner = cosOuter + penumbra;
    return smoothstep(cosOuter, cosInner, cosAngle);
}
