// Subgroup reductions where the driver offers them (NVIDIA's GL does; Mesa 22.3's llvmpipe does
// not): defines SUBGROUP_REDUCTION and enables the extensions that the reductions use. Include
// it first, before any declaration, as #extension must precede them; passes keep a
// shared-memory reduction for drivers without it, and both give the same bits.
#if defined(GL_KHR_shader_subgroup_arithmetic) && defined(GL_KHR_shader_subgroup_ballot)
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#extension GL_KHR_shader_subgroup_ballot : require
#define SUBGROUP_REDUCTION 1
#endif
