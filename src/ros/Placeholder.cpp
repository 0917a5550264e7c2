namespace pkm_accuracy {
namespace ros_layer {
int placeholder() { return 0; }
}  // namespace ros_layer
}  // namespace pkm_accuracy
