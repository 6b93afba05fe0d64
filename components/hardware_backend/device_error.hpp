#pragma once

// Why a device file could not be opened, in words a user acts on.

#include <cerrno>
#include <string>
#include <system_error>

namespace scancrew::hardware_backend {

// group: the Unix group that grants access to this kind of device ("video", "dialout").
inline std::string device_open_error(int err, const char* group) {
  switch (err) {
    case ENOENT:
    case ENODEV:
    case ENXIO:
      return "no such device";
    case EACCES:
    case EPERM:
      return std::string("permission denied; is the user in the '") + group + "' group?";
    case EBUSY:
      return "device busy";
    default:
      return std::generic_category().message(err);
  }
}

}  // namespace scancrew::hardware_backend
