#pragma once

// The report's 3D view script: web/report_viewer/main.js with three.js, bundled by esbuild
// into one minified classic script (IIFE) at build time (web/report_viewer/build.mjs, run by
// report/CMakeLists.txt), three.js's MIT licence notice at its top. It holds no "</script",
// so it can be inlined in a <script> element as it is.

namespace scancrew::report {

// The script, NUL-terminated, static: never freed.
const char* viewer_script();

}  // namespace scancrew::report
