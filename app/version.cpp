namespace chatterlab {
const char* version() { return CHATTERLAB_VERSION; }
}  // namespace chatterlab
