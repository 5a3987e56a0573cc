// What the response channel of a tap test measures.
#pragma once

namespace chatterlab {
namespace frf {

// The FRF is always reported as receptance (m/N); the response's kind fixes the conversion
// (see frf.h): acceleration / (-w^2), velocity / (j w), displacement as is.
enum class ResponseKind { kAcceleration, kVelocity, kDisplacement };

}  // namespace frf
}  // namespace chatterlab
