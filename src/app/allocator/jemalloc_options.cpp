// jemalloc's options for Penumbra's programs, read at their first allocation through jemalloc's
// documented `malloc_conf` symbol (MALLOC_CONF in the environment still overrides them).
//
// Pages freed are kept for reuse, never handed back to the system: a frame step of the
// discontinuity mesh frees and makes again lists of hundreds of megabytes in a large scene, and
// with jemalloc's default decay a fifth of a 10,000-polygon room's update step went to the kernel
// faulting and zeroing those pages afresh (1.24 million minor faults against 0.67 million over a
// build and ten steps; docs/shadows.md, session 42). The resident size stays at the run's peak,
// which every frame reaches anyway (+4.5% at the end of that run).
extern "C" {
// NOLINTNEXTLINE: the name and type are jemalloc's.
const char* malloc_conf = "dirty_decay_ms:-1,muzzy_decay_ms:-1";
}
