//! Carries the link directives for shaderc's static dependencies on Debian 12; it has no code.
