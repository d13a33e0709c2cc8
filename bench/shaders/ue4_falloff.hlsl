// Windowed inverse-square falloff of a punctual light (Karis 2013): the inverse square law,
// with 1 added to the squared distance, faded to 0 at the light's radius.
float Square(float x) { return x * x; }

float RadialAttenuation(float dist, float radius)
{
    float invRadius = 1.0 / radius;
    float ratio4 = Square(Square(dist * invRadius));
    float window = Square(saturate(1.0 - ratio4));
    return window / (dist * dist + 1.0);
}
