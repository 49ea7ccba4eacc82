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
shared Sums subgroup_sums[GROUP_INVOCATIONS];  // at most one per invocation, whatever the subgroup size
#else
shared Sums tree[GROUP_INVOCATIONS];
#endif

// The group's total of `mine` in invocation 0: a subgroup add and one barrier where the driver
// has subgroup arithmetic, else a shared-memory tree (log2 of the group's size barriers).
Sums group_sum(Sums mine, int local) {
#if SUBGROUP_SUM
    Sums subgroup_total = subgroupAdd(mine);
    if (subgroupElect()) subgroup_sums[gl_SubgroupID] = subgroup_total;
    barrier();
    Sums total = Sums(0.0);
    if (local == 0) {
        for (uint i = 0u; i < gl_NumSubgroups; ++i) total += subgroup_sums[i];
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
