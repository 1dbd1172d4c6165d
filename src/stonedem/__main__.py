from stonedem.cli import console

console()
