// SPDX-License-Identifier: MIT
// libcifs_occt_plugin.so: cifs::occt and OpenCASCADE in one module that the CLI opens (dlopen) the first
// time it meets a STEP or IGES file (apps/occt_plugin.cpp), so that a command on any other file does not
// load OCCT's libraries (0.1 s of CPU at every start). Its one export, cifs_occt_codec, is defined in
// occt.cpp (occt/CMakeLists.txt pulls it in and hides the rest): this file only gives the module a
// source, without the headers a definition here would parse.
