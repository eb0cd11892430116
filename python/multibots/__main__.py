from multibots.cli import main

main()
