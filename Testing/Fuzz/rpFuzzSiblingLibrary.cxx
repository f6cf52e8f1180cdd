// The fuzzers link the libraries' sources statically, those of the libraries loaded on first use
// too (rpSiblingLibrary.h: STL/OBJ, the .mrb zip): a sibling library's entry is then this
// executable's own exported symbol (the fuzzers link with ENABLE_EXPORTS), so the code behind the
// entries stays fuzzed.
#include <dlfcn.h>

#include "rpSiblingLibrary.h"

namespace rp {

void* SiblingLibrarySymbol(const void*, const std::string& library, const char* symbol, std::string& error, bool) {
  void* address = ::dlsym(RTLD_DEFAULT, symbol);
  if (!address) error = std::string(symbol) + " (of " + library + ") is not linked into this fuzzer";
  return address;
}

}  // namespace rp
