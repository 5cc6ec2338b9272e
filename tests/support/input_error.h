#pragma once
// Expected bad input: the message of the InputError a call throws.
#include <string>

#include "core/error.h"

namespace rfidray::testing {

// The message of the InputError that `f()` throws; "" when it throws none, so that EXPECT_EQ(…, "") checks a valid
// input and a find() in the message of an invalid one fails visibly. Any other exception propagates: a crash or
// a std::bad_alloc is no clean error.
template <class F>
std::string input_error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rfidray::testing
