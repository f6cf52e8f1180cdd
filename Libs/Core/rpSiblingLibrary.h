#pragma once
// A function from a shared object that lies beside the calling library and is loaded on first
// use: how a library keeps a heavy dependency (GDCM for JPEG 2000, ITK's transform IO with HDF5)
// out of every program that links it but rarely needs it. Loading a library maps and relocates it
// and everything it links, which costs more than most commands' work (Libs/ModuleCore).
#include <string>

namespace rp {

/// The address of `symbol` (an extern "C" function) in `library`, a file name looked for in the
/// folder of the shared object (or executable) that holds `anchor` — an address in the caller's
/// own code. The library is loaded once and never unloaded; thread-safe. nullptr with `error`
/// naming the file and the reason.
/// With `onlyIfLoaded`, the library is not loaded: nullptr (and no error) unless the process already holds it.
void* SiblingLibrarySymbol(const void* anchor, const std::string& library, const char* symbol, std::string& error,
                           bool onlyIfLoaded = false);

/// Typed: `Function` is the function pointer type of `symbol`.
template <typename Function>
Function SiblingLibraryFunction(const void* anchor, const std::string& library, const char* symbol, std::string& error,
                                bool onlyIfLoaded = false) {
  return reinterpret_cast<Function>(SiblingLibrarySymbol(anchor, library, symbol, error, onlyIfLoaded));
}

}  // namespace rp
