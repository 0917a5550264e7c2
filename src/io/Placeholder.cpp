// Placeholder translation unit until the YAML readers land.
namespace pkm_accuracy {
namespace io {
int placeholder() { return 0; }
}  // namespace io
}  // namespace pkm_accuracy
