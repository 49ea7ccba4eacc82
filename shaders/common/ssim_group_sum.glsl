// The work group's sum of the two SSIM reduction shaders (passes/ssim.comp, passes/ssim_strip.comp,
// docs/spec.md §6): included after the pass declares its work group's size (the subgroup
// built-ins need it), with GROUP_INVOCATIONS (a power of two), PREPARE and SQUARED_ERROR
// defined, and SUBGROUP_SUM where the pass enabled GL_KHR_shader_subgroup_arithmetic.
#if !PREPARE
#if SQUARED_ERROR
#define Sums vec2  // (SSIM, squared error)
#else
#define Sums float
#endif

#if SUBGROUP_SUM
// A slot per subgroup, SUBGROUP_SLOTS subgroups a round: one round for subgroups of 8 or more
// invocations (NVIDIA's 32, AMD's 32 or 64, Intel's 8 to 32) in groups of up to 256, more for
// smaller ones. Few slots, because the shared memory a group takes bounds how many groups a
// GPU keeps resident: on the H100, tiles taking 20 KiB a group ran 1.4-1.6x slower than 12.
const uint SUBGROUP_SLOTS = 32u;
shared Sums subgroup_sums[SUBGROUP_SLOTS];
#else
shared Sums tree[GROUP_INVOCATIONS];
#endif

// The group's total of `mine` in invocation 0: a subgroup add and one barrier where the driver
// has subgroup arithmetic, else a shared-memory tree (log2 of the group's size barriers).
Sums group_sum(Sums mine, int local) {
#if SUBGROUP_SUM
    Sums subgroup_total = subgroupAdd(mine);
    for (uint first = 0u; first < gl_NumSubgroups; first += SUBGROUP_SLOTS) {
        uint slot = gl_SubgroupID - first;  // wraps past the slots for earlier subgroups
        if (subgroupElect() && slot < SUBGROUP_SLOTS) {
            subgroup_sums[slot] = first == 0u ? subgroup_total : subgroup_sums[slot] + subgroup_total;
        }
        barrier();
    }
    Sums total = Sums(0.0);
    if (local == 0) {
        for (uint i = 0u; i < min(gl_NumSubgroups, SUBGROUP_SLOTS); ++i) total += subgroup_sums[i];
    }
    return total;
#else
    tree[local] = mine;
    barrier();
    for (int stride = GROUP_INVOCATIONS / 2; stride > 0; stride >>= 1) {
        if (local < stride) tree[local] += tree[local + stride];
        barrier();
    }
    return tree[0];
#endif
}
#endif
