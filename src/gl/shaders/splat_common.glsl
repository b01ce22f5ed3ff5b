// Shared by splat.comp and splat_resolve.comp: the fixed-point unit of the
// chord sums. One unit = radius / kChordScale; a uint then holds 2^32 / 2^15 / 2
// = 65,536 whole diameters per pixel (hundreds are typical), and one chord is
// rounded by at most 1.5e-5 r.
const float kChordScale = 32768.0;
