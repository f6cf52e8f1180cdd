#include "rpFormat.h"

#include <cstdarg>
#include <cstdio>

namespace rp {

std::string Format(const char* format, ...) {
  va_list args, again;
  va_start(args, format);
  va_copy(again, args);
  char text[256];
  const int length = std::vsnprintf(text, sizeof(text), format, args);
  va_end(args);
  std::string result;
  if (length < 0) {
    result = format;  // a format the C library refuses: the format itself says what was meant
  } else if (static_cast<size_t>(length) < sizeof(text)) {
    result.assign(text, static_cast<size_t>(length));
  } else {
    result.resize(static_cast<size_t>(length));
    std::vsnprintf(result.data(), result.size() + 1, format, again);
  }
  va_end(again);
  return result;
}

}  // namespace rp
