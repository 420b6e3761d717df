// Counter-based random numbers, shared verbatim by the C++ reference renderer and the GLSL shaders.
//
// Every random decision has its own number: a hash of (seed, pixel, sample, dimension). No generator
// state is carried along a path, so the GPU and the CPU draw identical numbers for the same decision,
// in any order and on any thread, and stochastic images can be compared pixel by pixel.
//
// The integer hash is Chris Wellons' "lowbias32" (hash-prospector, 2020): two multiply-xorshift rounds
// with bias about 0.17 of the ideal. Only 32-bit unsigned arithmetic is used, which C++ and GLSL define
// identically (wrap-around multiplication, logical shifts).
#ifndef VKRT_RANDOM_H
#define VKRT_RANDOM_H

#ifdef __cplusplus
#include <cstdint>
namespace vkrt {
using uint = uint32_t;
#define VKRT_FUNC inline
#else
#define VKRT_FUNC
#endif

// Every number drawn below is a multiple of VKRT_RANDOM_STEP (2^-24) in [0, 1): 24 random bits, exact in a float.
// Sampling tables whose cumulative probabilities lie on the same grid (host/scene/sampling_grid.h) choose alike
// on both devices, with the probabilities they state.
#define VKRT_RANDOM_STEPS 16777216u
#define VKRT_RANDOM_STEP 5.9604644775390625e-8

// Dimensions: the pixel jitter uses the first two, the lens the next two, the shutter time one; each node
// owns VKRT_DIMS_PER_NODE consecutive dimensions after those. Whitted's ray tree numbers its nodes as a binary
// heap (the camera ray's hit is node 0, the reflection child of node k is 2k + 1 and the transmission child
// 2k + 2); a path's bounce d is node d.
#define VKRT_DIM_PIXEL_X 0u
#define VKRT_DIM_PIXEL_Y 1u
#define VKRT_DIM_LENS_U 2u
#define VKRT_DIM_LENS_V 3u
#define VKRT_DIM_TIME 4u  // shutter time (motion blur), shared by the whole ray tree of a sample
#define VKRT_DIM_NODE_BASE 5u
#define VKRT_DIMS_PER_NODE 64u
// Light sample k of a node (up to VKRT_MAX_LIGHT_SAMPLES) uses dimensions 3k (which area light), 3k + 1 (where
// on it: both axes of the stratified pair) and 3k + 2 (the environment's direction: both axes).
#define VKRT_MAX_LIGHT_SAMPLES 16u
#define VKRT_DIM_LIGHT_PICK 0u
#define VKRT_DIM_LIGHT_U 1u
#define VKRT_DIM_LIGHT_ENVIRONMENT 2u
#define VKRT_DIM_LIGHT(k, which) (3u * (k) + (which))
// The traced specular lobe's microfacet normal (after the light samples' 48 dimensions).
#define VKRT_DIM_LOBE_U 48u
#define VKRT_DIM_LOBE_V 49u
// Whether a rough refracting dielectric keeps the microfacet normal it drew (shade_hit.h's compensatedMicroNormal):
// the pair's two numbers for the first two tries, hashed ones for later tries (vkrtLayered), whose normals take
// hashed numbers at VKRT_DIM_LOBE_U too.
#define VKRT_DIM_LOBE_ACCEPT 54u
// The path integrator's continuation through the untraced lobes (a cosine-distributed direction), and its
// choice of continuation (axis 0) and Russian roulette (axis 1).
#define VKRT_DIM_SCATTER_U 50u
#define VKRT_DIM_SCATTER_V 51u
#define VKRT_DIM_PATH_BRANCH 52u
// Whitted's Russian roulette of a branch weighted below the cut: a glossy reflection (axis 0), a glossy ray's
// transmission (axis 1).
#define VKRT_DIM_BRANCH_ROULETTE 53u
// The clear coat's lobe (KHR_materials_clearcoat): its microfacet normal, and whether the reflection follows it.
#define VKRT_DIM_COAT_U 56u
#define VKRT_DIM_COAT_V 57u
#define VKRT_DIM_COAT_PICK 58u
// Whether a ray goes on through the holes of alpha-blended surfaces (the node's last pair).
#define VKRT_DIM_COVERAGE 62u

VKRT_FUNC uint vkrtHash(uint x) {
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// A number's bits hash its seed, pixel, sample index and dimension in turn; chained hashing with distinct
// additive constants keeps (a, b) and (b, a) apart. The first two hashes are the pixel's stream, which the
// renderers work out once per pixel (ShadingContext), so that a number drawn from it takes the last two.
VKRT_FUNC uint vkrtPixelStream(uint seed, uint pixel) {
    return vkrtHash(vkrtHash(seed + 0x9e3779b9u) ^ (pixel + 0x85ebca6bu));
}

VKRT_FUNC uint vkrtStreamBits(uint stream, uint sampleIndex, uint dimension) {
    return vkrtHash(vkrtHash(stream ^ (sampleIndex + 0xc2b2ae35u)) ^ (dimension + 0x27d4eb2fu));
}

VKRT_FUNC uint vkrtRandomBits(uint seed, uint pixel, uint sampleIndex, uint dimension) {
    return vkrtStreamBits(vkrtPixelStream(seed, pixel), sampleIndex, dimension);
}

// A number in [0, 1) with 24 random bits, exactly representable as a float.
VKRT_FUNC float vkrtRandom(uint seed, uint pixel, uint sampleIndex, uint dimension) {
    return float(vkrtRandomBits(seed, pixel, sampleIndex, dimension) >> 8u) * VKRT_RANDOM_STEP;
}

// Bit reversal of a 32-bit word, written with shifts and masks so C++ and GLSL compute it alike.
VKRT_FUNC uint vkrtReverseBits(uint x) {
    x = ((x >> 1u) & 0x55555555u) | ((x & 0x55555555u) << 1u);
    x = ((x >> 2u) & 0x33333333u) | ((x & 0x33333333u) << 2u);
    x = ((x >> 4u) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4u);
    x = ((x >> 8u) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8u);
    return (x >> 16u) | (x << 16u);
}

// The second dimension of the Sobol' sequence; with the bit-reversed index (van der Corput) as the first,
// every run of 2^k consecutive points from the start is a (0,k,2)-net: stratified in every elementary
// interval (Sobol' 1967; Kollig and Keller, "Efficient multidimensional sampling", 2002).
//
// Its generator matrix is Pascal's triangle mod 2: index bit k contributes v_k = (1 + x)^k, with x a shift
// right by one from the top bit, so result bit 31 - j is the XOR of the index bits k with C(k, j) odd, which
// by Lucas's theorem are the k whose bits include j's. That XOR over supersets is a zeta transform over the
// subset lattice of the 5-bit positions, one step per position bit (Yates's algorithm): each step folds
// position i + 2^b onto i for the positions i without bit b. 15 operations and a bit reversal instead of a
// loop over 32 bits (which costs every lane all 32 iterations on a SIMD device); the same bits.
VKRT_FUNC uint vkrtSobol2(uint index) {
    uint x = index;
    x ^= (x >> 1u) & 0x55555555u;
    x ^= (x >> 2u) & 0x33333333u;
    x ^= (x >> 4u) & 0x0f0f0f0fu;
    x ^= (x >> 8u) & 0x00ff00ffu;
    x ^= x >> 16u;
    return vkrtReverseBits(x);
}

// vkrtSobol2 of the bit reversal of `reversed`, without reversing: each step of the transform mirrored (a shift
// right of the reversed word is a shift left of the word, and each mask is reversed).
VKRT_FUNC uint vkrtSobol2OfReversed(uint reversed) {
    uint x = reversed;
    x ^= (x << 1u) & 0xaaaaaaaau;
    x ^= (x << 2u) & 0xccccccccu;
    x ^= (x << 4u) & 0xf0f0f0f0u;
    x ^= (x << 8u) & 0xff00ff00u;
    x ^= x << 16u;
    return x;
}

// Where sample `sampleIndex` falls inside its pixel, in [0, 1)^2. The (0,2)-sequence is scrambled per
// pixel by XOR with random bits (which keeps the net property), so each pixel is stratified at every
// power-of-two sample count (progressive images converge as well as finished ones) and unbiased.
// `stream` is the pixel's (vkrtPixelStream).
VKRT_FUNC float vkrtPixelJitterX(uint stream, uint sampleIndex) {
    const uint scramble = vkrtStreamBits(stream, 0u, VKRT_DIM_PIXEL_X);
    return float((vkrtReverseBits(sampleIndex) ^ scramble) >> 8u) * VKRT_RANDOM_STEP;
}

VKRT_FUNC float vkrtPixelJitterY(uint stream, uint sampleIndex) {
    const uint scramble = vkrtStreamBits(stream, 0u, VKRT_DIM_PIXEL_Y);
    return float((vkrtSobol2(sampleIndex) ^ scramble) >> 8u) * VKRT_RANDOM_STEP;
}

// Laine and Karras's hash-based Owen scramble of the bits of x from the lowest up: each output bit depends
// only on the input bits below it (carries and even multipliers only move information upwards).
VKRT_FUNC uint vkrtLaineKarras(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

// A stratified sample for the dimension pair that starts at `dimension` (lens, time, light, lobe), `axis`
// 0 or 1 of it. Padding (Kollig and Keller 2002) with Burley's shuffle ("Practical Hash-based Owen
// Scrambling", JCGT 9(4), 2020): the pair takes the pixel's (0,2)-sequence at a sample index permuted by a
// nested uniform (Owen) scramble, which maps the first 2^k indices onto one aligned block of 2^k (whose
// points are again a (0,k,2)-net) and, being nonlinear, decorrelates the pairs; the point is then
// XOR-scrambled per pixel. So every dimension is stratified at every power-of-two sample count.
//
// The pair's key is the pixel stream's bits at sample index 0xffffffff (which no sample has) and the pair's
// dimension; its first hash, the pixel's `pairRoot` (vkrtPairRoot), is the same for every pair. The shuffled
// index is index = reverse(LK(reverse(sampleIndex), key)), so axis 0's bits, reverse(index), are LK(...)
// itself, and axis 1's, vkrtSobol2(index), are vkrtSobol2OfReversed(LK(...)).
VKRT_FUNC uint vkrtPairRoot(uint stream) { return vkrtHash(stream ^ (0xffffffffu + 0xc2b2ae35u)); }

VKRT_FUNC float vkrtStratifiedFrom(uint pairRoot, uint sampleIndex, uint dimension, uint axis) {
    const uint key = vkrtHash(pairRoot ^ (dimension + 0x27d4eb2fu));  // vkrtStreamBits(stream, 0xffffffffu, dimension)
    const uint shuffled = vkrtLaineKarras(vkrtReverseBits(sampleIndex), key);
    const uint bits = axis == 0u ? shuffled : vkrtSobol2OfReversed(shuffled);
    const uint scramble = vkrtHash(key ^ (0x68e31da4u + axis));
    return float((bits ^ scramble) >> 8u) * VKRT_RANDOM_STEP;
}

VKRT_FUNC float vkrtStratified(uint seed, uint pixel, uint sampleIndex, uint dimension, uint axis) {
    return vkrtStratifiedFrom(vkrtPairRoot(vkrtPixelStream(seed, pixel)), sampleIndex, dimension, axis);
}

// A number for the `layer`-th decision of one kind along a ray (the surfaces of alpha-blended geometry it
// meets, one after the other): the first two are the stratified pair at `dimension`, later ones are hashed
// from the pair's dimension and the layer. `stream` and `pairRoot` are the pixel's.
VKRT_FUNC float vkrtLayered(uint stream, uint pairRoot, uint sampleIndex, uint dimension, uint layer) {
    if (layer < 2u) return vkrtStratifiedFrom(pairRoot, sampleIndex, dimension, layer);
    const uint bits = vkrtHash(vkrtStreamBits(stream, sampleIndex, dimension) ^ (layer * 0x9e3779b9u));
    return float(bits >> 8u) * VKRT_RANDOM_STEP;
}

VKRT_FUNC uint vkrtNodeDimension(uint node, uint k) {
    return VKRT_DIM_NODE_BASE + node * VKRT_DIMS_PER_NODE + k;
}

#ifdef __cplusplus
}  // namespace vkrt
#endif
#undef VKRT_FUNC

#endif  // VKRT_RANDOM_H
