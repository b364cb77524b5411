from usvsim.cli.app import main

main()
