// Linked into every executable of the sanitizer build only (cmake/sanitizers.cmake).
//
// glfwTerminate() and Mesa's GLX teardown dlclose() the X11 extension libraries
// and the DRI driver (swrast_dri.so, llvmpipe) before the process exits. When
// LeakSanitizer then runs, those libraries are gone: memory their globals still
// pointed to looks leaked, and the stacks of what they did leak end in
// "<unknown module>", which no suppression can name. Keeping every library
// loaded until exit (this dlclose interposes glibc's: the executable's
// definition wins, and it is exported for libraries opened at run time) lets
// LeakSanitizer see their globals and name them, so tests/sanitizers/lsan.supp
// can suppress what Mesa, GLFW and X11 leak by library. Unloading early is
// never relied on: a library opened again is the same one.
extern "C" int dlclose(void*) {
    return 0;
}
