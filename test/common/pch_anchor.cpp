// The precompiled-header target of the tests (CMakeLists.txt: iraf_vo_test_pch) needs one source to compile.
