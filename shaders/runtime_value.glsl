// Values read at run time, never folded into the shader.
//
// lavapipe (Mesa 22.3) "inlines uniforms": at a pipeline's first draw it compiles a variant with
// the uniform values that decide a branch folded in as constants, and from then on keeps or drops
// it. So the first frame drawn with a pipeline could differ from later frames with the same
// pipeline in the last bit of a few values (issue 31: the first job of a configuration in a batch
// differed from later identical jobs by 1 ulp in ~60 of 370 000 values; a pipeline made afresh for
// every job made them equal). A material's switches and parameters that decide a branch are read
// through these functions: gl_FragCoord.x is never negative, so they return their argument, but no
// compiler can know that, so every frame takes the branch from the value — the same code in every
// frame, first or not (tests/batch_test.cpp, BatchCli.AJobGivesTheSameBytesFirstLaterAloneOrInAShard).
uint runtimeValue(uint x) { return x | uint(gl_FragCoord.x < 0.0); }
float runtimeValue(float x) { return gl_FragCoord.x < 0.0 ? -x : x; }
