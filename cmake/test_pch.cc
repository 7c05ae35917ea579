// The translation unit that compiles the test precompiled header (mostar_test_pch,
// cmake/MostarHelpers.cmake); it has no code of its own.
