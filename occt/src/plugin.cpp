// SPDX-License-Identifier: MIT
// libcifs_occt_plugin.so: cifs::occt and OpenCASCADE in one module that the CLI opens (dlopen) the first
// time it meets a STEP or IGES file (apps/occt_plugin.cpp), so that a command on any other file does not
// load OCCT's libraries (0.1 s of CPU at every start). Its only export is the C function below.
#include "cifs/occt/occt.hpp"

extern "C" __attribute__((visibility("default"))) void cifs_occt_codec(cifs::io::CadCodec* codec) {
  *codec = cifs::occt::cad_codec();
}
