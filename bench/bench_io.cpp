// placeholder while the stage is written
int main() { return 0; }
