// partc/precompiled.cpp: the translation unit that builds precompiled.hpp's
// precompiled header (CMake target partc_model_pch); it has nothing else.
