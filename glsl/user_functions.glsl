// Placeholder for a user's own versions of workshop functions (`vkpath check FILE.glsl`).
// At run time, vkpath resolves `#include "user_functions.glsl"` to the user's file and defines
// USER_FUNCTIONS and USER_DEFINES_<NAME> for every function the file defines; the embedded
// kernels are compiled without USER_FUNCTIONS, so they never include this file.
